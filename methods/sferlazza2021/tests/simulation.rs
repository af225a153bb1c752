//! The error dynamics (53) with a design for the §6 example: Lyapunov decrease, convergence, the ISS
//! bound of Theorem 3, and the sampling windows.

use std::sync::OnceLock;

use sporadic_sferlazza2021::design::{Design, DesignOptions, design};
use sporadic_sferlazza2021::example::{DISTURBANCE_BOUNDS, NOISE_BOUNDS, suspension};
use sporadic_sferlazza2021::iss::{IssConstants, IssOptions, iss_constants};
use sporadic_sferlazza2021::simulation::{SimulationOptions, simulate_error};
use sporadic_sferlazza2021::validation::GridPolicy;

/// A design of the §6 example on a coarse fixed grid (5·10³ points per window; fast), shared by the
/// tests. Theorem 3's certificate for its gains is checked by `iss_constants` (it fails otherwise).
fn fixture() -> &'static (Design, IssConstants) {
    static F: OnceLock<(Design, IssConstants)> = OnceLock::new();
    F.get_or_init(|| {
        let plant = suspension().unwrap();
        let s = DesignOptions {
            grid: GridPolicy::Spacing(1e-5),
            ..DesignOptions::default()
        };
        let d = design(&plant, &s).unwrap();
        let iss = iss_constants(
            d.gains(),
            &IssOptions {
                points_per_window: 1001,
            },
        )
        .unwrap();
        (d, iss)
    })
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// without noise, V (30) decreases strictly at every jump and does not
/// increase along flows, every inter-sample time lies in its sensor's window, and the error tends to 0.
#[test]
fn noise_free_lyapunov_decrease_and_convergence() {
    let (d, iss) = fixture();
    assert!(iss.min_m_eigenvalue.iter().all(|&m| m > 0.0));
    let plant = d.plant();
    let x0 = vec![0.1, 1.0, 0.05, 1.0];
    let mut s = SimulationOptions::noise_free(60.0, x0.clone());
    s.rho = iss.rho;
    s.record_step = 5e-3;
    let tr = simulate_error(d.gains(), &s).unwrap();
    assert!(tr.jumps.len() > 900, "{} jumps in 60 s", tr.jumps.len());
    for jm in &tr.jumps {
        assert!(
            jm.v_after < jm.v_before,
            "V increased at t = {}: {} → {}",
            jm.t,
            jm.v_before,
            jm.v_after
        );
        let w = plant.sensor(jm.sensor).unwrap().window();
        assert!(
            w.t1() - 1e-12 <= jm.tau && jm.tau <= w.t2() + 1e-12,
            "τ = {} outside {w:?}",
            jm.tau
        );
    }
    for i in 1..tr.t.len() {
        if tr.j[i] == tr.j[i - 1] {
            assert!(
                tr.v[i] <= tr.v[i - 1] * (1.0 + 1e-9),
                "V increased along a flow at t = {}",
                tr.t[i]
            );
        }
    }
    let ratio = norm(tr.x.last().unwrap()) / norm(&x0);
    assert!(ratio < 1e-3, "|x̃(60)|/|x̃(0)| = {ratio}");
    // The exponential bound (16) with d = w = 0 holds along the whole solution.
    for (t, x) in tr.t.iter().zip(&tr.x) {
        assert!(norm(x).powi(2) <= iss.error_bound_sq(*t, norm(&x0).powi(2), 0.0, 0.0));
    }
}

/// with the paper's disturbance and noise bounds the error stays within the ISS bound
/// (16) computed from the constants of Theorem 3's proof.
#[test]
fn noisy_error_within_iss_bound() {
    let (d, iss) = fixture();
    let x0 = vec![0.1, 1.0, 0.05, 1.0];
    let mut s = SimulationOptions::noise_free(10.0, x0.clone());
    s.rho = iss.rho;
    s.disturbance = Some(DISTURBANCE_BOUNDS.to_vec());
    s.noise = Some(NOISE_BOUNDS.iter().map(|&b| vec![b]).collect());
    s.seed = 7;
    let tr = simulate_error(d.gains(), &s).unwrap();
    assert!(tr.d_sup > 0.0 && tr.w_sup > 0.0);
    let d_max = DISTURBANCE_BOUNDS.iter().map(|b| b * b).sum::<f64>().sqrt();
    assert!(tr.d_sup <= d_max && tr.w_sup <= 0.02);
    let mut worst = 0.0f64;
    for (t, x) in tr.t.iter().zip(&tr.x) {
        let b = iss.error_bound_sq(*t, norm(&x0).powi(2), tr.d_sup, tr.w_sup);
        worst = worst.max(norm(x).powi(2) / b);
    }
    assert!(worst <= 1.0, "|x̃|² exceeds the ISS bound by {worst}");
    // The noise keeps the error away from zero but bounded.
    let tail =
        tr.x.iter()
            .skip(tr.x.len() / 2)
            .map(|x| norm(x))
            .fold(0.0f64, f64::max);
    assert!(tail > 0.0 && tail < norm(&x0));
}

#[test]
fn bad_simulation_settings() {
    let (d, _) = fixture();
    let s = SimulationOptions::noise_free(1.0, vec![1.0, 0.0]);
    assert!(simulate_error(d.gains(), &s).is_err());
    let s = SimulationOptions::noise_free(-1.0, vec![1.0, 0.0, 0.0, 0.0]);
    assert!(simulate_error(d.gains(), &s).is_err());
    let mut s = SimulationOptions::noise_free(1.0, vec![1.0, 0.0, 0.0, 0.0]);
    s.noise = Some(vec![vec![0.1]]);
    assert!(simulate_error(d.gains(), &s).is_err());
}
