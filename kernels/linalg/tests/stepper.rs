//! ExpmStepper against direct `expm_scaled` along long grids.

use faer::{Mat, mat};
use sporadic_linalg::InputError;
use sporadic_linalg::{DEFAULT_REANCHOR, LinalgError, expm_scaled, expm_stepper};

/// max_k ‖X̂_k − e^{Aτ_k}‖_max / ‖e^{Aτ_k}‖_max over the grid points with k % `every` == 0.
fn worst_error(
    a: &Mat<f64>,
    tau0: f64,
    h: f64,
    steps: usize,
    reanchor: usize,
    every: usize,
) -> f64 {
    let n = a.nrows();
    let mut st = expm_stepper(a.as_ref(), tau0, h, steps)
        .unwrap()
        .with_reanchor(reanchor)
        .unwrap();
    let mut out = Mat::<f64>::zeros(n, n);
    let mut worst = 0.0f64;
    let mut k = 0usize;
    while let Some(tau) = st.next_into(out.as_mut()) {
        assert_eq!(tau, tau0 + k as f64 * h);
        if k.is_multiple_of(every) {
            let direct = expm_scaled(a.as_ref(), tau).unwrap();
            worst = worst.max((&out - &direct).norm_max() / direct.norm_max());
        }
        k += 1;
    }
    assert_eq!(k, steps + 1);
    assert!(st.error().is_none());
    worst
}

/// 10⁵ steps of a lightly damped oscillator pair (n = 4, stack kernels): the error stays at the
/// level of a direct evaluation with re-anchoring, and grows without it.
#[test]
fn long_grid_small_order() {
    let a = mat![
        [-0.01, 1.0, 0.0, 0.0],
        [-1.0, -0.01, 0.2, 0.0],
        [0.0, 0.0, -0.02, 3.0],
        [0.0, 0.1, -3.0, -0.02]
    ];
    let steps = 100_000;
    let h = 1e-3;
    let with = worst_error(&a, 0.5, h, steps, DEFAULT_REANCHOR, 1);
    assert!(with < 2e-13, "with re-anchoring: {with:e}");
    let without = worst_error(&a, 0.5, h, steps, usize::MAX, 1);
    eprintln!(
        "n=4, 1e5 steps: worst relative error {with:e} (re-anchor every {DEFAULT_REANCHOR}), {without:e} (never)"
    );
    assert!(without > with);
}

/// Dense path (n = 12) along 2·10⁴ steps, compared at every 50th point.
#[test]
fn long_grid_dense_order() {
    let n = 12;
    let a = Mat::from_fn(n, n, |i, j| {
        let v = (((i * 7 + j * 13) % 11) as f64 - 5.0) / 20.0;
        if i == j { v - 0.3 } else { v }
    });
    let with = worst_error(&a, 0.0, 2e-3, 20_000, DEFAULT_REANCHOR, 50);
    assert!(with < 1e-12, "{with:e}");
}

#[test]
fn iterator_and_edge_cases() {
    let a = mat![[0.0, 1.0], [0.0, 0.0]];
    let items: Vec<Mat<f64>> = expm_stepper(a.as_ref(), 1.0, 0.5, 4).unwrap().collect();
    assert_eq!(items.len(), 5);
    for (k, x) in items.iter().enumerate() {
        let tau = 1.0 + 0.5 * k as f64;
        assert!((x - mat![[1.0, tau], [0.0, 1.0]]).norm_max() < 1e-15);
    }
    // h = 0 and negative h are fine.
    let back: Vec<Mat<f64>> = expm_stepper(a.as_ref(), 0.0, -1.0, 2).unwrap().collect();
    assert!((&back[2] - mat![[1.0, -2.0], [0.0, 1.0]]).norm_max() < 1e-15);
    assert_eq!(expm_stepper(a.as_ref(), 0.0, 0.0, 3).unwrap().count(), 4);
    // Wrong output shape: stops with a typed error instead of panicking.
    let mut st = expm_stepper(a.as_ref(), 0.0, 0.1, 3).unwrap();
    let mut wrong = Mat::<f64>::zeros(3, 3);
    assert_eq!(st.next_into(wrong.as_mut()), None);
    assert!(matches!(
        st.error(),
        Some(LinalgError::Input(InputError::DimensionMismatch {
            expected: 2,
            found: 3,
            ..
        }))
    ));
    assert!(matches!(
        expm_stepper(a.as_ref(), 0.0, 0.1, 3)
            .unwrap()
            .with_reanchor(0),
        Err(LinalgError::InvalidArgument(_))
    ));
    assert!(matches!(
        expm_stepper(a.as_ref(), f64::NAN, 0.1, 3),
        Err(LinalgError::Input(InputError::NonFinite { .. }))
    ));
    assert!(matches!(
        expm_stepper(Mat::<f64>::zeros(2, 1).as_ref(), 0.0, 0.1, 3),
        Err(LinalgError::Input(InputError::NotSquare { .. }))
    ));
}

/// A growing mode overflows during the run: the stepper stops with Overflow, never yields Inf.
#[test]
fn overflow_mid_run_is_reported() {
    let a = mat![[1.0, 0.0], [0.0, -1.0]];
    let mut st = expm_stepper(a.as_ref(), 0.0, 1.0, 2000).unwrap();
    let mut out = Mat::<f64>::zeros(2, 2);
    let mut last = 0.0;
    while let Some(tau) = st.next_into(out.as_mut()) {
        assert!(out.norm_max().is_finite());
        last = tau;
    }
    assert!(last > 700.0 && last < 710.0, "{last}");
    assert!(matches!(st.error(), Some(LinalgError::Overflow { .. })));
}
