//! Writes one figure of each kind for Ferrante et al. (2016): Example 1 (Fig. 1: |ε| and the Theorem 1
//! bound) and Example 2 (Fig. 2: ‖ε‖² projected on t and j), plus component, interval-bound and
//! eigenvalue-curve figures. Usage: `cargo run --release -p sporadic-figures --example gallery [out_dir]`.

use std::path::PathBuf;

use faer::{Mat, mat};
use sporadic_figures::{
    PlotSpec, Series, plot_components, plot_eigen_curves, plot_error_norm, plot_hybrid_time,
    plot_interval_bounds,
};
use sporadic_sim::{
    HybridObserver, LinearCorrection, LinearJump, LinearOutputs, LtiFlow, Periodic, Record,
    SampledPlant, SimError, SimOptions, UniformRandom, simulate, simulate_hybrid,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/figures".into()),
    );
    std::fs::create_dir_all(&dir)?;
    let e = std::f64::consts::E;

    // Example 1: A = M = 1, T = 1, L = 1.1 − 1/e; bound κ e^{−(γ/2)(t+j)} with the constants of Theorem 1.
    let l = 1.1 - 1.0 / e;
    let theta = (1.0 - (1.0 - (1.0 - l).powi(2) * e * e) / (e * e)).ln();
    let gamma = theta.abs() / 2.0;
    let kappa = e * (gamma / 2.0).exp();
    let flow = LtiFlow::new(mat![[1.0]].as_ref())?;
    let opts = SimOptions::new(30.0).record(Record::Every(0.05));
    let sim = simulate_hybrid(
        flow,
        LinearJump::new(mat![[1.0 - l]])?,
        &mut Periodic::new(1.0)?,
        &[1.0],
        &opts,
    )?;
    let (t, j) = (sim.arc.times(), sim.arc.jump_counters());
    let norm = sim.arc.norms();
    let bound: Vec<f64> = sim
        .arc
        .iter()
        .map(|(ht, _)| kappa * (-(gamma / 2.0) * (ht.t + ht.j as f64)).exp())
        .collect();
    plot_error_norm(
        dir.join("ferrante_fig1.svg"),
        &PlotSpec::new("Ferrante et al. Example 1", "t", "|e|"),
        t,
        j,
        &norm,
        Some(Series {
            label: "Theorem 1 bound",
            x: t,
            y: &bound,
        }),
    )?;

    // Example 2: mass–spring with sensor bias, L from the paper, intervals uniform in [0.2, 3].
    let a = mat![
        [0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 0.0],
        [-2.0, 1.0, -1.0, 0.0, 0.0],
        [2.0, -2.0, 0.0, -2.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0],
    ];
    let m = mat![[1.0, 0.0, 0.0, 0.0, 1.0]];
    let lg = mat![[0.77524], [0.18123], [-0.12123], [-0.17406], [0.22469]];
    let mut plant = SampledPlant {
        flow: LtiFlow::new(a.as_ref())?,
        output: LinearOutputs::new(vec![m.clone()])?,
    };
    let mut obs = HybridObserver {
        flow: LtiFlow::new(a.as_ref())?,
        jump: LinearCorrection::constant(m, lg)?,
    };
    let mut rule = UniformRandom::new(0.2, 3.0, 1)?.with_first_window(0.0, 3.0)?;
    let opts = SimOptions::new(60.0).record(Record::Every(0.05));
    let sim = simulate(
        &mut plant,
        &mut obs,
        &mut rule,
        &[1.0, -1.0, 0.5, 0.0, 1.0],
        &[0.0; 5],
        &opts,
    )?;
    let err = sim.error_arc()?;
    let sq: Vec<f64> = err.norms().iter().map(|v| v * v).collect();
    let (t, j) = (err.times(), err.jump_counters());
    plot_hybrid_time(
        dir.join("ferrante_fig2.svg"),
        &PlotSpec::new("Squared error norm", "t", "|e|^2").log_y(),
        t,
        j,
        &[("|e|^2", &sq)],
    )?;
    let comps: Vec<Vec<f64>> = (0..5).map(|k| err.component(k)).collect::<Result<_, _>>()?;
    let names = ["e1", "e2", "e3", "e4", "bias error"];
    let series: Vec<(&str, &[f64])> = names
        .iter()
        .zip(&comps)
        .map(|(n, c)| (*n, c.as_slice()))
        .collect();
    plot_components(
        dir.join("ferrante_components.svg"),
        &PlotSpec::new("Error components", "t", "e"),
        t,
        j,
        &series,
    )?;

    // Interval bounds around the plant position (illustrative band of ±|e1|).
    let x1 = sim.plant_arc()?.component(0)?;
    let lo: Vec<f64> = x1
        .iter()
        .zip(&comps[0])
        .map(|(x, e)| x - e.abs() - 0.05)
        .collect();
    let hi: Vec<f64> = x1
        .iter()
        .zip(&comps[0])
        .map(|(x, e)| x + e.abs() + 0.05)
        .collect();
    plot_interval_bounds(
        dir.join("bounds.svg"),
        &PlotSpec::new("Bounds on z1", "t", "z1"),
        t,
        j,
        &lo,
        &hi,
        &x1,
    )?;

    // Spectral radius of e^{Av}(I − LM) against v ∈ [0.2, 3] (independent reference
    // implementation: max 0.95882 at v = 0.2).
    let jm = Mat::<f64>::identity(5, 5)
        - mat![[0.77524], [0.18123], [-0.12123], [-0.17406], [0.22469]]
            * mat![[1.0, 0.0, 0.0, 0.0, 1.0]];
    let v: Vec<f64> = (0..=280).map(|k| 0.2 + 0.01 * k as f64).collect();
    let rho: Vec<f64> = v
        .iter()
        .map(|&s| {
            Ok(sporadic_linalg::spectral_radius(
                (sporadic_linalg::expm_scaled(a.as_ref(), s)? * &jm).as_ref(),
            )?)
        })
        .collect::<Result<_, SimError>>()?;
    let one: Vec<f64> = v.iter().map(|_| 1.0).collect();
    plot_eigen_curves(
        dir.join("spectral_radius.svg"),
        &PlotSpec::new("Spectral radius of the error jump", "v", "rho"),
        &[
            Series {
                label: "rho(e^{Av}(I-LM))",
                x: &v,
                y: &rho,
            },
            Series {
                label: "1",
                x: &v,
                y: &one,
            },
        ],
    )?;
    println!("figures written to {}", dir.display());
    Ok(())
}
