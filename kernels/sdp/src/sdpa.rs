//! Reading and writing the SDPA sparse format (`.dat-s`), the format of SDPLIB.
//!
//! # Sign conventions
//!
//! SDPA states the pair (SDPLIB README, "The SDPA format")
//!
//! ```text
//! (SDPA-P)  min  cᵀx            s.t.  X = Σ_i x_i F_i − F_0 ⪰ 0
//! (SDPA-D)  max  ⟨F_0, Y⟩        s.t.  ⟨F_i, Y⟩ = c_i (i = 1..m),  Y ⪰ 0
//! ```
//!
//! while this crate solves (see [`crate::problem`])
//!
//! ```text
//! (P)  min ⟨C, X⟩   s.t. ⟨A_i, X⟩ = b_i,  X ⪰ 0
//! (D)  max bᵀy      s.t. Σ_i y_i A_i + S = C,  S ⪰ 0.
//! ```
//!
//! Put `C = −F_0`, `A_i = −F_i`, `b = −c` (the mapping of SDPT3's `read_sdpa.m`). Then
//!
//! * (D) reads `max −cᵀy` s.t. `S = C − Σ y_i A_i = Σ y_i F_i − F_0 ⪰ 0`: this is (SDPA-P) with
//!   **`x = y`** and SDPA's primal matrix `X_SDPA = S`; its value is `cᵀx = −bᵀy`.
//! * (P) reads `min −⟨F_0, X⟩` s.t. `⟨F_i, X⟩ = c_i`: this is (SDPA-D) with **`Y = X`**; its value
//!   is `⟨F_0, Y⟩ = −⟨C, X⟩`.
//!
//! So every objective changes sign: the SDPLIB optimal values ("SDPA sign convention") equal
//! `−bᵀy* = −⟨C, X*⟩`. [`sdpa_objectives`] converts a [`Solution`]. Infeasibility also swaps
//! names: SDPLIB's *primal infeasible* problems (`infp*`, the LMI `Σ x_i F_i − F_0 ⪰ 0` has no
//! solution) are [`Status::DualInfeasible`] here, and its *dual infeasible* ones (`infd*`) are
//! [`Status::PrimalInfeasible`]; see [`sdpa_status_name`].
//!
//! # Accepted syntax
//!
//! Following the SDPLIB README and the quirks of the real files:
//!
//! 1. any number of leading comment lines whose first non-blank character is `"` or `*`
//!    (such lines are also skipped anywhere later in the file), and blank lines;
//! 2. `m`, then `nblocks`, each the first token of its own line — the rest of the line (e.g.
//!    `=mdim`) is ignored;
//! 3. the `nblocks` block sizes, a negative size denoting a diagonal (LP) block;
//! 4. the objective vector `c` (`m` numbers, possibly over several lines, `+1.0` style signs);
//! 5. entries `matno blkno i j value`, `matno = 0` for `F_0`, all indices 1-based; entries with
//!    `i > j` are mirrored to the upper triangle and duplicates are summed.
//!
//! In the header, the characters `, ( ) { }` separate tokens like blanks, and everything from
//! an `=` to the end of the line is ignored. Any deviation — missing or extra tokens, an index
//! outside its range, an off-diagonal entry in an LP block, a NaN or infinite number — is an
//! [`SdpError::SdpaFormat`] naming the 1-based line; no input makes the reader panic.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::SdpError;
use crate::problem::{BlockKind, Problem, ProblemBuilder};
use crate::solver::{Solution, Status};

/// Parses an SDPA sparse-format problem (see the [module documentation](self) for the format and
/// the sign convention `C = −F_0`, `A_i = −F_i`, `b = −c`).
pub fn read_sdpa(text: &str) -> Result<Problem, SdpError> {
    Parser::new(text).parse()
}

/// Reads and parses an SDPA sparse-format file.
///
/// I/O failures are [`SdpError::Io`]; bytes that are not UTF-8 are an [`SdpError::SdpaFormat`]
/// at the line where they occur.
pub fn read_sdpa_file(path: impl AsRef<Path>) -> Result<Problem, SdpError> {
    let path = path.as_ref();
    let bytes =
        std::fs::read(path).map_err(|e| SdpError::Io(format!("{}: {e}", path.display())))?;
    match String::from_utf8(bytes) {
        Ok(text) => read_sdpa(&text),
        Err(e) => {
            let valid = e.utf8_error().valid_up_to();
            let line = 1 + e.as_bytes()[..valid]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            Err(SdpError::SdpaFormat {
                line,
                reason: "invalid UTF-8".to_string(),
            })
        }
    }
}

/// Writes a problem in SDPA sparse format (inverse of [`read_sdpa`]: `F_0 = −C`, `F_i = −A_i`,
/// `c = −b`).
///
/// Numbers are printed in shortest round-trip form, so `read_sdpa(&write_sdpa(p)) == p` for every
/// problem built by [`ProblemBuilder`].
pub fn write_sdpa(problem: &Problem) -> String {
    let mut out = String::new();
    // `fmt::Write` for `String` cannot fail.
    let _ = writeln!(
        out,
        "\"written by sporadic-sdp: F0 = -C, Fi = -A_i, c = -b (SDPA sign convention)"
    );
    let _ = writeln!(out, "{} =mdim", problem.b.len());
    let _ = writeln!(out, "{} =nblocks", problem.blocks.len());
    let sizes: Vec<String> = problem
        .blocks
        .iter()
        .map(|bd| match bd.block.kind {
            BlockKind::Psd => bd.block.size.to_string(),
            BlockKind::Lp => format!("-{}", bd.block.size),
        })
        .collect();
    let _ = writeln!(out, "{}", sizes.join(" "));
    let c: Vec<String> = problem.b.iter().map(|&v| format!("{:e}", -v)).collect();
    let _ = writeln!(out, "{}", c.join(" "));
    for (k, bd) in problem.blocks.iter().enumerate() {
        for (i, j, v) in bd.c.iter() {
            let _ = writeln!(out, "0 {} {} {} {:e}", k + 1, i + 1, j + 1, -v);
        }
    }
    // Constraint matrices in constraint order (as SDPA files usually are).
    let mut order: Vec<(usize, usize, usize)> = Vec::new();
    for (k, bd) in problem.blocks.iter().enumerate() {
        for (pos, (i, _)) in bd.a.iter().enumerate() {
            order.push((*i, k, pos));
        }
    }
    order.sort_unstable();
    for (i, k, pos) in order {
        for (r, s, v) in problem.blocks[k].a[pos].1.iter() {
            let _ = writeln!(out, "{} {} {} {} {:e}", i + 1, k + 1, r + 1, s + 1, -v);
        }
    }
    out
}

/// Objective values of a solution in the SDPA sign convention, comparable with SDPLIB's table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SdpaObjectives {
    /// `cᵀx` of (SDPA-P), equal to `−bᵀy` (minus [`Solution::dual_objective`]).
    pub primal: f64,
    /// `⟨F_0, Y⟩` of (SDPA-D), equal to `−⟨C, X⟩` (minus [`Solution::primal_objective`]).
    pub dual: f64,
}

/// Converts the objectives of a solution of a problem read with [`read_sdpa`] to the SDPA
/// convention (see the [module documentation](self)).
pub fn sdpa_objectives(solution: &Solution) -> SdpaObjectives {
    SdpaObjectives {
        primal: -solution.dual_objective,
        dual: -solution.primal_objective,
    }
}

/// The SDPLIB/SDPA name of a status, for people (the infeasibility names swap, see the
/// [module documentation](self)); [`sdpa_status_id`] is the machine-readable form.
pub fn sdpa_status_name(status: Status) -> &'static str {
    match status {
        Status::Optimal => "optimal",
        Status::AlmostOptimal => "almost optimal",
        Status::PrimalInfeasible => "SDPA dual infeasible",
        Status::DualInfeasible => "SDPA primal infeasible",
        Status::MaxIterations => "iteration limit",
        Status::Interrupted => "interrupted",
        Status::NumericalTrouble => "numerical trouble",
        Status::Accepted => "accepted",
    }
}

/// The snake-case identifier of a status in the SDPA naming (used in JSON output): `optimal`,
/// `almost_optimal`, `sdpa_dual_infeasible` ([`Status::PrimalInfeasible`]),
/// `sdpa_primal_infeasible` ([`Status::DualInfeasible`]), `iteration_limit`, `interrupted`,
/// `numerical_trouble`, `accepted`.
pub fn sdpa_status_id(status: Status) -> &'static str {
    match status {
        Status::Optimal => "optimal",
        Status::AlmostOptimal => "almost_optimal",
        Status::PrimalInfeasible => "sdpa_dual_infeasible",
        Status::DualInfeasible => "sdpa_primal_infeasible",
        Status::MaxIterations => "iteration_limit",
        Status::Interrupted => "interrupted",
        Status::NumericalTrouble => "numerical_trouble",
        Status::Accepted => "accepted",
    }
}

/// A token with the line it came from.
struct Token<'a> {
    text: &'a str,
    line: usize,
}

struct Parser<'a> {
    lines: std::iter::Peekable<std::iter::Enumerate<std::str::Lines<'a>>>,
    /// Line number of the last line consumed (for end-of-file errors).
    last_line: usize,
}

fn is_separator(c: char) -> bool {
    c.is_whitespace() || matches!(c, ',' | '(' | ')' | '{' | '}')
}

fn is_comment(line: &str) -> bool {
    matches!(line.trim_start().chars().next(), Some('"' | '*'))
}

/// The tokens of a line, with everything after an `=` removed.
fn header_tokens(line: &str) -> impl Iterator<Item = &str> {
    let line = line.split('=').next().unwrap_or("");
    line.split(is_separator).filter(|t| !t.is_empty())
}

fn format_err(line: usize, reason: impl Into<String>) -> SdpError {
    SdpError::SdpaFormat {
        line,
        reason: reason.into(),
    }
}

fn parse_usize(tok: &Token<'_>, what: &str) -> Result<usize, SdpError> {
    let t = tok.text.strip_prefix('+').unwrap_or(tok.text);
    if t.is_empty() || !t.bytes().all(|b| b.is_ascii_digit()) {
        return Err(format_err(
            tok.line,
            format!(
                "expected {what} (a nonnegative integer), found `{}`",
                tok.text
            ),
        ));
    }
    t.parse::<usize>()
        .map_err(|_| format_err(tok.line, format!("{what} `{}` is too large", tok.text)))
}

fn parse_isize(tok: &Token<'_>, what: &str) -> Result<(bool, usize), SdpError> {
    match tok.text.strip_prefix('-') {
        Some(rest) => parse_usize(
            &Token {
                text: rest,
                line: tok.line,
            },
            what,
        )
        .map(|v| (true, v)),
        None => parse_usize(tok, what).map(|v| (false, v)),
    }
}

fn parse_f64(tok: &Token<'_>, what: &str) -> Result<f64, SdpError> {
    // Rust's parser also accepts "inf"/"nan" spellings; those are rejected below as non-finite.
    let v: f64 = tok.text.parse().map_err(|_| {
        format_err(
            tok.line,
            format!("expected {what} (a number), found `{}`", tok.text),
        )
    })?;
    if !v.is_finite() {
        return Err(format_err(
            tok.line,
            format!("non-finite {what} `{}`", tok.text),
        ));
    }
    Ok(v)
}

impl<'a> Parser<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            lines: text.lines().enumerate().peekable(),
            last_line: 0,
        }
    }

    /// Next line that is neither blank nor a comment, as `(1-based line number, text)`.
    fn next_content_line(&mut self) -> Option<(usize, &'a str)> {
        for (idx, line) in self.lines.by_ref() {
            self.last_line = idx + 1;
            if line.trim().is_empty() || is_comment(line) {
                continue;
            }
            return Some((idx + 1, line));
        }
        None
    }

    /// First header token of the next content line (the rest of the line is ignored).
    fn leading_token(&mut self, what: &str) -> Result<Token<'a>, SdpError> {
        loop {
            let Some((line, text)) = self.next_content_line() else {
                return Err(format_err(
                    self.last_line.max(1),
                    format!("unexpected end of file: expected {what}"),
                ));
            };
            if let Some(t) = header_tokens(text).next() {
                return Ok(Token { text: t, line });
            }
            // A line holding only punctuation or an `=` comment: keep looking.
        }
    }

    /// Exactly `count` header tokens, possibly spread over several lines. Extra tokens on the
    /// last line are an error when `strict_tail` holds and ignored otherwise.
    fn header_list(
        &mut self,
        count: usize,
        what: &str,
        strict_tail: bool,
        mut sink: impl FnMut(Token<'a>) -> Result<(), SdpError>,
    ) -> Result<(), SdpError> {
        let mut got = 0usize;
        while got < count {
            let Some((line, text)) = self.next_content_line() else {
                return Err(format_err(
                    self.last_line.max(1),
                    format!("unexpected end of file: expected {count} {what}, found {got}"),
                ));
            };
            for t in header_tokens(text) {
                if got == count {
                    if strict_tail {
                        return Err(format_err(
                            line,
                            format!("more than the expected {count} {what} (extra token `{t}`)"),
                        ));
                    }
                    break;
                }
                sink(Token { text: t, line })?;
                got += 1;
            }
        }
        Ok(())
    }

    fn parse(mut self) -> Result<Problem, SdpError> {
        let m_tok = self.leading_token("the number of constraints m")?;
        let m = parse_usize(&m_tok, "the number of constraints m")?;
        let nb_tok = self.leading_token("the number of blocks")?;
        let nblocks = parse_usize(&nb_tok, "the number of blocks")?;

        let mut blocks: Vec<(BlockKind, usize)> = Vec::new();
        self.header_list(nblocks, "block sizes", false, |tok| {
            let (neg, size) = parse_isize(&tok, "a block size")?;
            if size == 0 {
                return Err(format_err(tok.line, "block size 0"));
            }
            blocks.push((if neg { BlockKind::Lp } else { BlockKind::Psd }, size));
            Ok(())
        })?;

        let mut c: Vec<f64> = Vec::new();
        self.header_list(m, "objective coefficients", true, |tok| {
            c.push(parse_f64(&tok, "objective coefficient")?);
            Ok(())
        })?;

        let mut builder = ProblemBuilder::new(m);
        for (kind, size) in &blocks {
            builder.add_block(*kind, *size);
        }
        for (i, &ci) in c.iter().enumerate() {
            builder.set_b(i, -ci);
        }

        while let Some((line, text)) = self.next_content_line() {
            let mut toks = text
                .split(is_separator)
                .filter(|t| !t.is_empty())
                .map(|t| Token { text: t, line });
            let mut next = |what: &str| {
                toks.next().ok_or_else(|| {
                    format_err(
                        line,
                        format!(
                            "entry line needs 5 fields `matno blkno i j value`; {what} missing"
                        ),
                    )
                })
            };
            let matno = parse_usize(&next("matno")?, "matrix number")?;
            let blkno = parse_usize(&next("blkno")?, "block number")?;
            let i = parse_usize(&next("i")?, "row index")?;
            let j = parse_usize(&next("j")?, "column index")?;
            let value = parse_f64(&next("value")?, "entry value")?;
            if let Some(extra) = toks.next() {
                return Err(format_err(
                    line,
                    format!("entry line has more than 5 fields (extra `{}`)", extra.text),
                ));
            }
            if matno > m {
                return Err(format_err(
                    line,
                    format!("matrix number {matno} exceeds m = {m}"),
                ));
            }
            if blkno == 0 || blkno > nblocks {
                return Err(format_err(
                    line,
                    format!("block number {blkno} outside 1..={nblocks}"),
                ));
            }
            let (kind, size) = blocks[blkno - 1];
            if i == 0 || j == 0 || i > size || j > size {
                return Err(format_err(
                    line,
                    format!("entry ({i},{j}) outside block {blkno} of size {size}"),
                ));
            }
            if kind == BlockKind::Lp && i != j {
                return Err(format_err(
                    line,
                    format!("off-diagonal entry ({i},{j}) in diagonal block {blkno}"),
                ));
            }
            if matno == 0 {
                builder.add_c(blkno - 1, i - 1, j - 1, -value);
            } else {
                builder.add_a(matno - 1, blkno - 1, i - 1, j - 1, -value);
            }
        }
        // Every index was validated above, so `build` cannot fail on structure; map any residual
        // error (e.g. a sum of huge duplicates overflowing to infinity) to a format error.
        builder.build().map_err(|e| match e {
            SdpError::NonFinite { location, value } => format_err(
                self.last_line.max(1),
                format!("summing duplicate entries gives {value} at {location}"),
            ),
            other => other,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The example of the SDPLIB README (SDPA format section).
    const README_EXAMPLE: &str = "\"A sample problem.
2 =mdim
2 =nblocks
{2, 2}
10.0 20.0
0 1 1 1 1.0
0 1 2 2 2.0
0 2 1 1 3.0
0 2 2 2 4.0
1 1 1 1 1.0
1 1 2 2 1.0
2 1 2 2 1.0
2 2 1 1 5.0
2 2 1 2 2.0
2 2 2 2 6.0
";

    #[test]
    fn readme_example_maps_signs() {
        let p = read_sdpa(README_EXAMPLE).unwrap();
        assert_eq!(p.b, vec![-10.0, -20.0]);
        assert_eq!(p.blocks.len(), 2);
        assert_eq!(
            p.blocks[0].c.iter().collect::<Vec<_>>(),
            vec![(0, 0, -1.0), (1, 1, -2.0)]
        );
        // A_2 in block 2 = −[[5,2],[2,6]] stored as its upper triangle.
        let a2 = &p.blocks[1].a[0];
        assert_eq!(a2.0, 1);
        assert_eq!(
            a2.1.iter().collect::<Vec<_>>(),
            vec![(0, 0, -5.0), (0, 1, -2.0), (1, 1, -6.0)]
        );
    }

    #[test]
    fn quirks_are_accepted() {
        let text = "* comment\n\" another\n 2 = m\n 3\n(2, -3 ,1) =blocks\n{+1.0,\n-2.5E0}\n\
                    1 1 2 1 4.0\n1 1 1 2 1.0\n0 2 3 3 -0.0\n2 3 1 1 7\n\n* trailing comment\n";
        let p = read_sdpa(text).unwrap();
        assert_eq!(p.b, vec![-1.0, 2.5]);
        assert_eq!(p.blocks[1].block.kind, BlockKind::Lp);
        assert_eq!(p.blocks[1].block.size, 3);
        // (2,1) mirrored onto (1,2) and summed with the explicit (1,2).
        assert_eq!(
            p.blocks[0].a[0].1.iter().collect::<Vec<_>>(),
            vec![(0, 1, -5.0)]
        );
        assert_eq!(
            p.blocks[2].a[0].1.iter().collect::<Vec<_>>(),
            vec![(0, 0, -7.0)]
        );
    }

    #[test]
    fn errors_name_the_line() {
        let cases: &[(&str, usize)] = &[
            ("", 1),
            ("2\n1\n2\n1.0\n", 4),                  // c too short (EOF)
            ("1\n1\n2\n1.0 2.0\n", 4),              // c too long
            ("1\n1\n2\n1.0\n1 1 3 1 1.0\n", 5),     // index out of block
            ("1\n1\n-2\n1.0\n1 1 1 2 1.0\n", 5),    // off-diagonal in LP block
            ("1\n1\n2\n1.0\n2 1 1 1 1.0\n", 5),     // matno > m
            ("1\n1\n2\n1.0\n1 2 1 1 1.0\n", 5),     // blkno > nblocks
            ("1\n1\n2\n1.0\n1 1 1 1 nan\n", 5),     // NaN
            ("1\n1\n2\ninf\n", 4),                  // infinite c
            ("1\n1\n2\n1.0\n1 1 1 1\n", 5),         // missing field
            ("1\n1\n2\n1.0\n1 1 1 1 1 1\n", 5),     // extra field
            ("x\n", 1),                             // bad m
            ("1\n1\n0\n1.0\n", 3),                  // zero block size
            ("1\n1\n99999999999999999999999\n", 3), // overflowing size
        ];
        for &(text, line) in cases {
            match read_sdpa(text) {
                Err(SdpError::SdpaFormat { line: l, .. }) => assert_eq!(l, line, "{text:?}"),
                other => panic!("{text:?}: expected a format error, got {other:?}"),
            }
        }
    }

    #[test]
    fn write_then_read_round_trips() {
        let p = read_sdpa(README_EXAMPLE).unwrap();
        let text = write_sdpa(&p);
        assert_eq!(read_sdpa(&text).unwrap(), p);
    }
}
