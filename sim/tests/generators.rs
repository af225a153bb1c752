//! Sampling-sequence generators: windows respected, order preserved, reproducible, seed-dependent.

use proptest::prelude::*;
use sporadic_linalg::InputError;
use sporadic_sim::{
    BoundedUniform, IntervalSequence, NoiseSource, RoundRobin, SampleInterval, UniformRandom,
};

fn intervals(seq: &mut dyn IntervalSequence, n: usize) -> Vec<SampleInterval> {
    seq.take_intervals(n).unwrap()
}

#[test]
fn uniform_random_inside_window_and_reproducible() {
    let draw = |seed| intervals(&mut UniformRandom::new(0.2, 3.0, seed).unwrap(), 5000);
    let a = draw(42);
    assert!(
        a.iter()
            .all(|s| (0.2..=3.0).contains(&s.interval) && s.sensor == 0)
    );
    assert_eq!(a, draw(42));
    assert_ne!(a, draw(43));
    // The draws fill the window: mean ≈ 1.6 (std. error 0.011), extremes near the ends.
    let mean = a.iter().map(|s| s.interval).sum::<f64>() / a.len() as f64;
    assert!((mean - 1.6).abs() < 0.05, "mean {mean}");
    let (lo, hi) = a.iter().fold((f64::MAX, f64::MIN), |(l, h), s| {
        (l.min(s.interval), h.max(s.interval))
    });
    assert!(lo < 0.21 && hi > 2.99, "range [{lo}, {hi}]");
}

#[test]
fn first_window_is_honoured() {
    let mut g = UniformRandom::new(0.2, 3.0, 1)
        .unwrap()
        .with_first_window(0.0, 3.0)
        .unwrap();
    let v = intervals(&mut g, 3);
    assert!((0.0..=3.0).contains(&v[0].interval));
    assert!(
        UniformRandom::new(0.2, 3.0, 1)
            .unwrap()
            .with_first_window(2.0, 1.0)
            .is_err()
    );
}

#[test]
fn round_robin_order_and_windows() {
    // Sferlazza et al. §6: σ = 1 in [0.02, 0.07], σ = 2 in [0.04, 0.09] (sensors 0 and 1 here), plus a third.
    let w = [(0.02, 0.07), (0.04, 0.09), (0.5, 0.5)];
    let v = intervals(
        &mut RoundRobin::new(&w, 9).unwrap().starting_at(1).unwrap(),
        3000,
    );
    for (k, s) in v.iter().enumerate() {
        assert_eq!(s.sensor, (k + 1) % 3, "order broken at {k}");
        let (lo, hi) = w[s.sensor];
        assert!(
            (lo..=hi).contains(&s.interval),
            "interval {k} = {} outside [{lo}, {hi}]",
            s.interval
        );
    }
    assert_eq!(
        v,
        intervals(
            &mut RoundRobin::new(&w, 9).unwrap().starting_at(1).unwrap(),
            3000
        )
    );
    assert_ne!(
        v,
        intervals(
            &mut RoundRobin::new(&w, 10).unwrap().starting_at(1).unwrap(),
            3000
        )
    );
    assert!(RoundRobin::new(&w, 0).unwrap().starting_at(3).is_err());
    assert!(RoundRobin::new(&[], 0).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn any_valid_window_is_respected(t1 in 1e-3f64..2.0, width in 0.0f64..2.0, seed in any::<u64>()) {
        let t2 = t1 + width;
        let v = intervals(&mut UniformRandom::new(t1, t2, seed).unwrap(), 200);
        prop_assert!(v.iter().all(|s| s.interval >= t1 && s.interval <= t2));
        let mut noise = BoundedUniform::new(vec![-t1, 0.0], vec![t2, width], seed).unwrap();
        let mut out = [0.0; 2];
        for k in 0..200 {
            noise.sample(k as f64, &mut out);
            prop_assert!(out[0] >= -t1 && out[0] <= t2 && out[1] >= 0.0 && out[1] <= width);
        }
    }

    #[test]
    fn invalid_windows_are_typed_errors(t1 in -2.0f64..2.0, t2 in -2.0f64..2.0) {
        let ok = t1 > 0.0 && t1 <= t2;
        prop_assert_eq!(UniformRandom::new(t1, t2, 0).is_ok(), ok);
        let is_window_error = matches!(UniformRandom::new(t1, t2, 0), Err(sporadic_sim::SimError::Input(InputError::InvalidWindow { .. })));
        prop_assert_eq!(is_window_error, !ok);
    }
}
