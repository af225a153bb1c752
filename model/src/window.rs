//! Sampling windows: every interval between two consecutive samples lies in `[T1, T2]`.

use serde::{Deserialize, Serialize};
use sporadic_linalg::InputError;
use sporadic_linalg::input::{LowerEnd, check_window};

/// A sampling window `[T1, T2]`, `0 < T1 ≤ T2 < ∞`: the class of sampling sequences whose
/// intervals `t_{k+1} − t_k` all lie in it (Ferrante et al. 2016, Problem 1; Etienne et al.
/// 2017, `S[τ_low, τ̄]`; Rabehi et al. 2021, Assumption 1; Sferlazza et al. 2021, (4) per
/// sensor).
///
/// Serialised as the pair `[T1, T2]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "[f64; 2]", into = "[f64; 2]")]
pub struct SamplingWindow {
    t1: f64,
    t2: f64,
}

impl SamplingWindow {
    /// The window `[t1, t2]`; both ends finite, `0 < t1 ≤ t2`.
    pub fn new(t1: f64, t2: f64) -> Result<Self, InputError> {
        check_window("sampling window [T1, T2]", t1, t2, LowerEnd::Positive)?;
        Ok(Self { t1, t2 })
    }

    /// The periodic window `[T, T]`.
    pub fn periodic(t: f64) -> Result<Self, InputError> {
        Self::new(t, t)
    }

    /// Shortest interval `T1`.
    pub fn t1(&self) -> f64 {
        self.t1
    }

    /// Longest interval `T2`.
    pub fn t2(&self) -> f64 {
        self.t2
    }

    /// Whether `T1 = T2` (periodic sampling).
    pub fn is_periodic(&self) -> bool {
        self.t1 == self.t2
    }

    /// Whether `other ⊆ self`.
    pub fn contains(&self, other: &SamplingWindow) -> bool {
        self.t1 <= other.t1 && other.t2 <= self.t2
    }

    /// The same window with the upper end `t2` (an error if `t2 < T1`).
    pub fn with_t2(&self, t2: f64) -> Result<Self, InputError> {
        Self::new(self.t1, t2)
    }

    /// The same window with the lower end `t1` (an error if `t1 > T2` or `t1 ≤ 0`).
    pub fn with_t1(&self, t1: f64) -> Result<Self, InputError> {
        Self::new(t1, self.t2)
    }
}

impl TryFrom<[f64; 2]> for SamplingWindow {
    type Error = InputError;
    fn try_from([t1, t2]: [f64; 2]) -> Result<Self, InputError> {
        Self::new(t1, t2)
    }
}

impl From<SamplingWindow> for [f64; 2] {
    fn from(w: SamplingWindow) -> Self {
        [w.t1, w.t2]
    }
}

impl std::fmt::Display for SamplingWindow {
    /// `[T1, T2]` with the ends at 6 significant digits.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "[{}, {}]", significant(self.t1), significant(self.t2))
    }
}

/// `x` rounded to 6 significant digits and printed in its shortest form: plain decimals in
/// `[1e-4, 1e6)`, exponent form outside (`1e300`, not 301 digits).
pub fn significant(x: f64) -> String {
    shortest(x, 6, 1e-4..1e6)
}

/// `x` rounded to 4 significant digits in its shortest form, for messages: plain decimals in
/// `[1e-3, 1e4)`, exponent form outside (`1.695e5`, not `169500`).
pub fn sig4(x: f64) -> String {
    shortest(x, 4, 1e-3..1e4)
}

/// `x` rounded to `digits` significant digits, printed as plain decimals when its magnitude
/// is in `plain`, in exponent form otherwise.
fn shortest(x: f64, digits: usize, plain: std::ops::Range<f64>) -> String {
    let r = format!("{x:.*e}", digits - 1).parse::<f64>().unwrap_or(x);
    if r != 0.0 && r.is_finite() && !plain.contains(&r.abs()) {
        format!("{r:e}")
    } else {
        format!("{r}")
    }
}

/// `x` as `2^k` (or `-2^k`) when it is exactly a power of two other than `1` (a balancing
/// scale of a normal form, which is exact in floating point), else `None` (then print it with
/// [`significant`] or [`sig4`]).
pub fn power_of_two(x: f64) -> Option<String> {
    let k = x.abs().log2().round();
    (x.is_finite() && x != 0.0 && x.abs() != 1.0 && x.abs() == k.exp2())
        .then(|| format!("{}2^{k}", if x < 0.0 { "-" } else { "" }))
}

/// The sampling of a plant's outputs: one window for all outputs, or round-robin sensors each
/// with its own window (Sferlazza et al. 2021: sensor `σ` is read when the time since the
/// previous sample lies in its window).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sampling {
    /// Every output sampled at once, intervals in the window.
    Synchronous(SamplingWindow),
    /// Round-robin sensors, in polling order, one window per sensor.
    RoundRobin(Vec<SamplingWindow>),
}

impl Sampling {
    /// The windows: one, or one per sensor.
    pub fn windows(&self) -> &[SamplingWindow] {
        match self {
            Sampling::Synchronous(w) => std::slice::from_ref(w),
            Sampling::RoundRobin(ws) => ws,
        }
    }

    /// The smallest lower end over the windows (the `T1` a window search keeps fixed).
    pub fn t1(&self) -> f64 {
        self.windows()
            .iter()
            .map(|w| w.t1())
            .fold(f64::INFINITY, f64::min)
    }

    /// The largest upper end over the windows.
    pub fn t2(&self) -> f64 {
        self.windows().iter().map(|w| w.t2()).fold(0.0, f64::max)
    }

    /// The sampling with every window's upper end set to `max(T1_σ, t2)`: the family a search on
    /// `T2` explores (for one window, simply `[T1, t2]`).
    pub fn with_t2(&self, t2: f64) -> Result<Self, InputError> {
        let map = |w: &SamplingWindow| w.with_t2(t2.max(w.t1()));
        Ok(match self {
            Sampling::Synchronous(w) => Sampling::Synchronous(w.with_t2(t2)?),
            Sampling::RoundRobin(ws) => {
                Sampling::RoundRobin(ws.iter().map(map).collect::<Result<_, _>>()?)
            }
        })
    }

    /// The sampling with every window's lower end set to `min(T2_σ, t1)`.
    pub fn with_t1(&self, t1: f64) -> Result<Self, InputError> {
        let map = |w: &SamplingWindow| w.with_t1(t1.min(w.t2()));
        Ok(match self {
            Sampling::Synchronous(w) => Sampling::Synchronous(w.with_t1(t1)?),
            Sampling::RoundRobin(ws) => {
                Sampling::RoundRobin(ws.iter().map(map).collect::<Result<_, _>>()?)
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_numbers_are_short() {
        assert_eq!(significant(0.253029), "0.253029");
        assert_eq!(significant(3.1234567), "3.12346");
        assert_eq!(significant(1e300), "1e300");
        assert_eq!(significant(-1.23456789e-300), "-1.23457e-300");
        assert_eq!(significant(0.0), "0");
        assert_eq!(significant(f64::INFINITY), "inf");
        assert!(significant(12345678.9).len() < 12);
    }

    #[test]
    fn exact_powers_of_two_print_as_powers() {
        assert_eq!(power_of_two(0.125).as_deref(), Some("2^-3"));
        assert_eq!(power_of_two(-1024.0).as_deref(), Some("-2^10"));
        assert_eq!(power_of_two(2f64.powi(-1074)).as_deref(), Some("2^-1074"));
        for x in [1.0, -1.0, 0.0, 3.0, 0.1, f64::INFINITY, f64::NAN] {
            assert_eq!(power_of_two(x), None, "{x}");
        }
    }

    #[test]
    fn windows_are_validated() {
        assert!(SamplingWindow::new(0.1, 0.5).is_ok());
        assert!(SamplingWindow::new(0.5, 0.1).is_err());
        assert!(SamplingWindow::new(0.0, 0.1).is_err());
        assert!(SamplingWindow::new(0.1, f64::INFINITY).is_err());
        assert!(SamplingWindow::new(f64::NAN, 1.0).is_err());
        assert!(SamplingWindow::periodic(1.0).unwrap().is_periodic());
    }

    #[test]
    fn windows_serialise_as_pairs_and_are_checked_on_input() {
        let w = SamplingWindow::new(0.2, 3.0).unwrap();
        assert_eq!(serde_json::to_string(&w).unwrap(), "[0.2,3.0]");
        let back: SamplingWindow = serde_json::from_str("[0.2,3.0]").unwrap();
        assert_eq!(back, w);
        assert!(serde_json::from_str::<SamplingWindow>("[3.0,0.2]").is_err());
        assert_eq!(w.to_string(), "[0.2, 3]");
    }

    #[test]
    fn round_robin_search_moves_every_upper_end() {
        let s = Sampling::RoundRobin(vec![
            SamplingWindow::new(0.02, 0.07).unwrap(),
            SamplingWindow::new(0.04, 0.09).unwrap(),
        ]);
        assert_eq!(s.t1(), 0.02);
        let s2 = s.with_t2(0.03).unwrap();
        assert_eq!(s2.windows()[0], SamplingWindow::new(0.02, 0.03).unwrap());
        assert_eq!(s2.windows()[1], SamplingWindow::new(0.04, 0.04).unwrap());
    }
}
