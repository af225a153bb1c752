//! A problem whose solution is far larger than the scale of the default starting point: the
//! restart of `sporadic_sdp::Solver::solve`.
//!
//! `data/sferlazza_synthesis_short_window.dat-s` is the synthesis SDP (47) of Sferlazza et al.
//! (2021), `min p_M s.t. Ξ(τ) ⪰ 2μI (τ ∈ {T1, T2}), I ⪯ P ⪯ p_M I` with `μ = 0.01`, for a fuzzed
//! marginal plant of order 5 with two outputs on the window `[0.00425701, 0.0045]` (written with
//! `sporadic_sdp::write_sdpa` from the LMI model the crate builds): 16 variables, blocks of order
//! 8, 8, 5 and 5. Its optimum has `p_M ≈ 1.22·10⁶` against data of order one. From SDPT3's
//! default point the iterates stalled with steps of `10⁻⁴` and ended in numerical trouble after
//! 14 iterations (the method reported "solver stopped with numerical_trouble" for a window whose
//! super-windows it certified). Reference: CSDP 6.2.0 on the same file gives up after 61
//! iterations ("lack of progress") with objectives 1.2208222e6 (primal) and 1.2207896e6 (dual).

mod common;

use common::solve_data_file_to_optimality;
use sporadic_sdp::sdpa_objectives;

#[test]
fn a_solution_far_beyond_the_starting_scale_is_reached_by_the_restart() {
    let (_, sol) = solve_data_file_to_optimality("sferlazza_synthesis_short_window.dat-s");
    // The first run stalls (which is why the restart exists); if it ever converges, this
    // problem no longer tests the restart and another one is needed.
    assert!(sol.restarted, "the first run converged: {sol:?}");
    assert!(sol.iterations <= 60, "{} iterations", sol.iterations);
    // The optimum lies between CSDP's last primal and dual objectives.
    let obj = sdpa_objectives(&sol);
    for v in [obj.primal, obj.dual] {
        assert!(
            (1.2207896e6..=1.2208222e6).contains(&v),
            "objective {v} outside CSDP's bracket [1.2207896e6, 1.2208222e6]"
        );
    }
}
