//! Regression tests for ill-conditioned end games, where the normal equations of the HKM
//! direction lose `𝒜(ΔX) = r_p` and the solver must switch to the least-squares form (module
//! docs of `sporadic_sdp::solver`).
//!
//! `data/ferrante_min_trP.dat-s` is the SDP of `min tr P s.t. P ⪰ I, Φ_i ⪯ −I` (16 vertices,
//! LMI (41) of Ferrante et al., Automatica 2016, Example 2) exported from the LMI layer by
//! `observers/ferrante2016/tests/example2.rs`: 40 variables (P symmetric 5×5, F full 5×5), one
//! 5×5 block and sixteen 15×15 blocks. Its LMI side has an unbounded optimal face (F can grow
//! along a ray without changing tr P), so `y` and `S` drift to `‖y‖ ≈ 10⁴…10⁵` while `μ → 0`.
//! Reference: CSDP 6.2.0 (`csdp data/ferrante_min_trP.dat-s`, run on this machine) reports
//! "Success" after 27 iterations with primal/dual objectives 9.0457655e+02 / 9.0457656e+02,
//! relative gap 7.3e-9 and DIMACS errors ≤ 1e-7.

mod common;

use common::solve_data_file_to_optimality;
use sporadic_sdp::sdpa_objectives;

#[test]
fn observer_design_lmi_with_unbounded_optimal_face_is_solved_to_tolerance() {
    let (_, sol) = solve_data_file_to_optimality("ferrante_min_trP.dat-s");
    assert!(sol.iterations <= 40, "{} iterations", sol.iterations);
    // CSDP's objectives bracket the optimum to its printed 8 digits.
    let obj = sdpa_objectives(&sol);
    for v in [obj.primal, obj.dual] {
        assert!(
            (v - 904.576555).abs() <= 2e-5,
            "objective {v} differs from CSDP's 904.57655…904.57656"
        );
    }
}
