//! Failure exits and options of the §5.3 loop (fast grids; the full paper-grid run is in
//! `suspension.rs`).

use faer::mat;
use sporadic_sferlazza2021::Error;
use sporadic_sferlazza2021::SamplingWindow;
use sporadic_sferlazza2021::design::{DesignLoop, DesignOptions, design};
use sporadic_sferlazza2021::example::suspension;
use sporadic_sferlazza2021::plant::{RoundRobinPlant, window_contains};
use sporadic_sferlazza2021::validation::{
    ExponentialBound, GridPolicy, SCREEN_POINTS, ValidationOptions, XiFamily, grid_spacing,
};

fn fast() -> DesignOptions {
    DesignOptions {
        grid: GridPolicy::Spacing(1e-4),
        ..DesignOptions::default()
    }
}

#[test]
fn iteration_cap_is_reported() {
    let plant = suspension().unwrap();
    let s = DesignOptions {
        max_iterations: 1,
        ..fast()
    };
    assert!(matches!(
        design(&plant, &s),
        Err(Error::NotConverged { iterations: 1 })
    ));
}

/// Stepping by hand: the first synthesis has p* = 65.3705 (an independent Python/Clarabel run); every failing sensor adds
/// exactly its worst grid point, which then belongs to T_σ; the loop ends with all sensors passing.
#[test]
fn loop_by_hand() {
    let plant = suspension().unwrap();
    let mut lp = DesignLoop::new(&plant, &fast()).unwrap();
    assert!(lp.bound().lyapunov_margin > 0.0);
    let mut passed = false;
    for _ in 0..10 {
        passed = lp.step().unwrap();
        let r = lp.log().last().unwrap();
        for (s, v) in r.sensors.iter().enumerate() {
            assert_eq!(v.passed(), r.added[s].is_none());
            if let Some(t) = r.added[s] {
                assert_eq!(t, v.argmin_tau);
                assert!(v.min_is_exact && v.min_eigenvalue <= 0.01);
                assert!(window_contains(plant.sensor(s).unwrap().window(), t));
            }
        }
        if passed {
            break;
        }
    }
    assert!(passed);
    let first_p_star = lp.log()[0].p_star;
    assert!(
        (first_p_star / 65.3705 - 1.0).abs() < 1e-4,
        "{first_p_star}"
    );
    assert_eq!(lp.log()[0].points, vec![vec![0.02, 0.07], vec![0.04, 0.09]]);
    let d = lp.finish().unwrap();
    assert!(d.p_star >= first_p_star - 1e-6);
    // Each later synthesis contains every point added before it.
    for w in d.log.windows(2) {
        for s in 0..2 {
            let added = w[0].added[s].map_or(0, |_| 1);
            assert_eq!(w[1].points[s].len(), w[0].points[s].len() + added);
        }
    }
}

/// A window containing the aliasing period of an oscillator: the Proposition 1 screen rejects the plant;
/// without the screen, (47) is infeasible at the window's end point.
#[test]
fn undetectable_window_fails_cleanly() {
    let w = 3.0;
    let t = std::f64::consts::PI / w;
    let plant = RoundRobinPlant::new(
        mat![[0.0, w], [-w, 0.0]].as_ref(),
        &[(
            mat![[1.0, 0.0]].as_ref(),
            SamplingWindow::new(t - 0.2, t).unwrap(),
        )],
    )
    .unwrap();
    assert!(matches!(
        design(&plant, &fast()),
        Err(Error::NotDetectable { .. })
    ));
    let s = DesignOptions {
        detectability: None,
        ..fast()
    };
    assert!(matches!(design(&plant, &s), Err(Error::Infeasible { .. })));
}

#[test]
fn grid_cap_and_policies() {
    let plant = suspension().unwrap();
    let s = DesignOptions {
        validation: ValidationOptions {
            max_points: 1e5,
            ..ValidationOptions::default()
        },
        ..DesignOptions::default()
    };
    let mut lp = DesignLoop::new(&plant, &s).unwrap();
    assert!(matches!(
        lp.step(),
        Err(Error::GridTooLarge { sigma: 1, .. })
    ));
    // The rigorous spacing is far finer than (49) for this example (≈ 1.5·10² times).
    let b = ExponentialBound {
        beta: 13.2,
        gamma: 22.5156,
    };
    let paper = grid_spacing(&plant, 1, GridPolicy::Paper, 0.01, 65.3705, &b).unwrap();
    let rigorous = grid_spacing(&plant, 1, GridPolicy::Rigorous, 0.01, 65.3705, &b).unwrap();
    assert!(
        (paper / 2.0 / 5.71e-9 - 1.0).abs() < 2e-3,
        "δ* = {}",
        paper / 2.0
    );
    assert!(
        (paper / rigorous / (2.0 * 73.86) - 1.0).abs() < 1e-2,
        "{}",
        paper / rigorous
    );
    let s = DesignOptions {
        fixed_bound: Some(ExponentialBound {
            beta: 1.0,
            gamma: 0.5,
        }),
        ..fast()
    };
    assert!(DesignLoop::new(&plant, &s).is_err());
    let s = DesignOptions { mu: -1.0, ..fast() };
    assert!(DesignLoop::new(&plant, &s).is_err());
}

/// With `proof_pieces`, a large (49) grid is replaced by a proof of (48) over the whole window
/// where one succeeds: on the example of §6 (4.4·10⁶ grid points per sensor) the iterates are
/// those of the grid-only loop (a failing iteration is decided, and its τ̄ of (50) found, by the
/// grid), the last iteration is proven for every sensor, and its `P_σ` satisfy (48) at 10⁴
/// fresh points of each window.
#[test]
fn proof_replaces_the_grid_without_changing_the_iterates() {
    let plant = suspension().unwrap();
    let grid_only = design(&plant, &DesignOptions::default()).unwrap();
    let proven = design(
        &plant,
        &DesignOptions {
            proof_pieces: Some(4096),
            ..DesignOptions::default()
        },
    )
    .unwrap();
    let stars =
        |d: &sporadic_sferlazza2021::Design| d.log.iter().map(|r| r.p_star).collect::<Vec<_>>();
    assert_eq!(stars(&grid_only), stars(&proven));
    let last = proven.log.last().unwrap();
    assert!(last.passed());
    for (s, v) in last.sensors.iter().enumerate() {
        assert!(v.proof_pieces.is_some(), "sensor {}: {v:?}", s + 1);
        assert_eq!((v.points, v.failures), (0, 0));
        let w = plant.sensor(s).unwrap().window();
        let taus: Vec<f64> = (0..10_000)
            .map(|k| w.t1() + (w.t2() - w.t1()) * k as f64 / 9_999.0)
            .collect();
        let fam = XiFamily::new(&plant, &proven.p, s).unwrap();
        let check = fam
            .validate_points(&taus, proven.mu, &ValidationOptions::default())
            .unwrap();
        assert!(check.passed(), "sensor {}: {check:?}", s + 1);
    }
    for r in &proven.log[..proven.log.len() - 1] {
        assert!(
            r.sensors
                .iter()
                .any(|v| !v.passed() && v.proof_pieces.is_none())
        );
    }
}

/// Issue 22: a (49) grid above the cap (here 10⁵ points against 4.4·10⁶) ends the step with
/// `GridTooLarge` when no proof is allowed (the design command's paper grid, above), but with
/// `proof_pieces` it is decided without running it: an iteration whose `Ξ_σ` the floating-point
/// screen of the window shows not positive definite somewhere (confirmed in interval
/// arithmetic) adds that τ, one the proof of (48) over the window disproves adds the failing
/// τ (an end of the failing piece, where λ_min(Ξ_σ(τ)) ≤ μ), and the loop ends with every
/// sensor proven.
#[test]
fn grid_above_the_cap_is_decided_by_the_proof() {
    let plant = suspension().unwrap();
    let s = DesignOptions {
        validation: ValidationOptions {
            max_points: 1e5,
            ..ValidationOptions::default()
        },
        proof_pieces: Some(4096),
        ..DesignOptions::default()
    };
    let mut lp = DesignLoop::new(&plant, &s).unwrap();
    let mut passed = false;
    let (mut screened, mut disproved) = (0, 0);
    for _ in 0..10 {
        passed = lp.step().unwrap();
        let r = lp.log().last().unwrap();
        println!("iteration {}: added {:?}", r.iteration, r.added);
        for (sigma, v) in r.sensors.iter().enumerate() {
            let fam = XiFamily::new(&plant, &r.p, sigma).unwrap();
            match r.added[sigma] {
                // The screen's points, or none: no grid above the cap is run.
                Some(t) if v.points == SCREEN_POINTS => {
                    assert!(!v.passed() && v.min_eigenvalue < 0.0, "{v:?}");
                    assert!(fam.min_eigenvalue(t).unwrap() < 0.0);
                    screened += 1;
                }
                Some(t) => {
                    assert_eq!(v.points, 0, "{v:?}");
                    assert!(!v.passed() && v.min_eigenvalue <= 0.01, "{v:?}");
                    assert!(fam.min_eigenvalue(t).unwrap() <= 0.01);
                    disproved += 1;
                }
                None => assert!(
                    v.passed() && v.proof_pieces.is_some() && v.points == 0,
                    "{v:?}"
                ),
            }
        }
        if passed {
            break;
        }
    }
    println!("{screened} τ added by the screen, {disproved} by a disproof of the proof");
    assert!(passed);
    assert!(
        screened + disproved > 0,
        "no iteration was decided by a disproof"
    );
}
