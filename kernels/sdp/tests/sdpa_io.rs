//! SDPA reader/writer: robustness against malformed input and write→read round trips.

use proptest::prelude::*;
use sporadic_sdp::{BlockKind, Problem, ProblemBuilder, SdpError, read_sdpa, write_sdpa};

/// The README example of SDPLIB plus every syntactic quirk the reader accepts.
const VALID: &[&str] = &[
    "\"A sample problem.\n2 =mdim\n2 =nblocks\n{2, 2}\n10.0 20.0\n0 1 1 1 1.0\n0 1 2 2 2.0\n\
     0 2 1 1 3.0\n0 2 2 2 4.0\n1 1 1 1 1.0\n1 1 2 2 1.0\n2 1 2 2 1.0\n2 2 1 1 5.0\n2 2 1 2 2.0\n\
     2 2 2 2 6.0\n",
    "* c\n 3\n 2\n 3 -2\n{+1.0,+1.0,\n-2.5E0}\n 0 1 1 1 1.750000\n1 1 1 2 -0.5\n1 1 2 1 0.5\n\
     2 2 2 2 2.000000000000000111e-01\n3 1 3 3 1\n3 2 1 1 -1\n",
];

fn check_no_panic(text: &str) {
    match read_sdpa(text) {
        Ok(p) => {
            // Whatever was accepted must round-trip.
            assert_eq!(read_sdpa(&write_sdpa(&p)).unwrap(), p);
        }
        Err(SdpError::SdpaFormat { line, .. }) => {
            assert!(line >= 1 && line <= text.lines().count().max(1));
        }
        Err(other) => panic!("unexpected error kind {other:?}"),
    }
}

/// Random problem with every block kind, duplicates, both triangles and negative zeros.
fn random_problem() -> impl Strategy<Value = Problem> {
    (
        0usize..5,
        prop::collection::vec((any::<bool>(), 1usize..5), 1..4),
        prop::collection::vec(
            (0usize..6, 0usize..4, 0usize..5, 0usize..5, -1e3f64..1e3),
            0..40,
        ),
        prop::collection::vec(-1e3f64..1e3, 5),
    )
        .prop_map(|(m, blocks, entries, b)| {
            let mut pb = ProblemBuilder::new(m);
            for (psd, n) in &blocks {
                pb.add_block(if *psd { BlockKind::Psd } else { BlockKind::Lp }, *n);
            }
            for i in 0..m {
                pb.set_b(i, b[i]);
            }
            for (mat, blk, i, j, v) in entries {
                let blk = blk % blocks.len();
                let (psd, n) = blocks[blk];
                let (i, j) = (i % n, if psd { j % n } else { i % n });
                if mat == 0 || m == 0 {
                    pb.add_c(blk, i, j, v);
                } else {
                    pb.add_a((mat - 1) % m, blk, i, j, v);
                }
            }
            pb.build().expect("valid random problem")
        })
}

proptest! {
    // Bounded run time in CI: 256 cases per property (well under a second each in release
    // mode; the reader's allocations are bounded by the input length) and a cap on shrinking,
    // so that even a failure reports within seconds instead of shrinking without limit.
    #![proptest_config(ProptestConfig {
        cases: 256,
        max_shrink_iters: 2_000,
        max_shrink_time: 10_000,
        ..ProptestConfig::default()
    })]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        check_no_panic(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn arbitrary_token_soup_never_panics(
        toks in prop::collection::vec(
            prop_oneof![
                Just("1".to_string()), Just("2".to_string()), Just("-1".to_string()),
                Just("0".to_string()), Just("\n".to_string()), Just("{".to_string()),
                Just("}".to_string()), Just(",".to_string()), Just("=x".to_string()),
                Just("nan".to_string()), Just("inf".to_string()), Just("1e308".to_string()),
                Just("99999999999999999999999".to_string()), Just("\"".to_string()),
                (0u32..6).prop_map(|v| v.to_string()),
                (-10.0f64..10.0).prop_map(|v| format!("{v:e}")),
            ],
            0..80,
        )
    ) {
        check_no_panic(&toks.join(" "));
    }

    #[test]
    fn mutated_valid_files_never_panic(
        which in 0usize..VALID.len(),
        op in 0usize..5,
        pos in any::<prop::sample::Index>(),
        pos2 in any::<prop::sample::Index>(),
        junk in prop_oneof![
            Just("NaN"), Just("-inf"), Just("1e999"), Just("18446744073709551616"),
            Just("-3"), Just("0"), Just("x"), Just("{"), Just("1.5"), Just("4294967296"),
        ],
    ) {
        let text = VALID[which];
        let mutated = match op {
            // Truncation at an arbitrary character.
            0 => {
                let cut = pos.index(text.len() + 1);
                let cut = (0..=cut).rev().find(|&c| text.is_char_boundary(c)).unwrap_or(0);
                text[..cut].to_string()
            }
            // Swap two tokens.
            1 | 2 => {
                let mut toks: Vec<&str> = text.split(' ').collect();
                let (a, b) = (pos.index(toks.len()), pos2.index(toks.len()));
                toks.swap(a, b);
                toks.join(" ")
            }
            // Replace one token by junk (huge index, NaN, …).
            3 => {
                let mut toks: Vec<&str> = text.split(' ').collect();
                let a = pos.index(toks.len());
                toks[a] = junk;
                toks.join(" ")
            }
            // Delete a line.
            _ => {
                let mut lines: Vec<&str> = text.lines().collect();
                let a = pos.index(lines.len());
                lines.remove(a);
                lines.join("\n")
            }
        };
        check_no_panic(&mutated);
    }

    #[test]
    fn write_read_round_trip(p in random_problem()) {
        let text = write_sdpa(&p);
        prop_assert_eq!(read_sdpa(&text).unwrap(), p);
    }
}

#[test]
fn huge_and_non_finite_values_are_format_errors() {
    for (text, line) in [
        ("1\n1\n2\n1e999\n", 4),
        ("1\n1\n2\n1.0\n1 1 1 1 NaN\n", 5),
        ("1\n1\n2\n1.0\n1 1 1 18446744073709551616 1.0\n", 5),
        ("1\n1\n2\n1.0\n18446744073709551615 1 1 1 1.0\n", 5),
        ("18446744073709551616\n", 1),
    ] {
        match read_sdpa(text) {
            Err(SdpError::SdpaFormat { line: l, .. }) => assert_eq!(l, line, "{text:?}"),
            other => panic!("{text:?}: {other:?}"),
        }
    }
}

#[test]
fn duplicate_entries_sum_and_mirror() {
    let p = read_sdpa("1\n1\n2\n1\n1 1 1 2 1.5\n1 1 2 1 2.5\n1 1 1 2 -1\n").unwrap();
    // −(1.5 + 2.5 − 1) on (0,1).
    assert_eq!(
        p.blocks[0].a[0].1.iter().collect::<Vec<_>>(),
        vec![(0, 1, -3.0)]
    );
}

/// Every SDPLIB file the solver tests use reads, and write→read reproduces it exactly.
#[test]
fn sdplib_files_round_trip() {
    let Some(dir) = std::env::var_os("SPORADIC_SDPLIB") else {
        eprintln!(
            "SDPLIB round-trip test SKIPPED: SPORADIC_SDPLIB is not set \
             (e.g. SPORADIC_SDPLIB=/work/shared/sdplib)"
        );
        return;
    };
    let dir = std::path::PathBuf::from(dir);
    for name in [
        "control1", "hinf1", "truss1", "theta1", "arch0", "mcp100", "qap5", "infp1",
    ] {
        let p = sporadic_sdp::read_sdpa_file(dir.join(format!("{name}.dat-s"))).unwrap();
        let again = read_sdpa(&write_sdpa(&p)).unwrap();
        assert_eq!(again, p, "{name}");
    }
    // Header checks against the README table (m and the number of blocks in the file).
    let arch0 = sporadic_sdp::read_sdpa_file(dir.join("arch0.dat-s")).unwrap();
    assert_eq!(arch0.b.len(), 174);
    assert_eq!(arch0.blocks[1].block.kind, BlockKind::Lp);
    assert_eq!(arch0.blocks[1].block.size, 174);
}
