//! Solution files in CSDP's format (Borchers, CSDP user's guide; `write_sol`/`read_sol` of
//! CSDP 6), read and written for the problems of this crate.
//!
//! # Format
//!
//! ```text
//! y_1 y_2 … y_m                 first line: the dual vector y
//! 1 b i j v                     entry (i, j) of block b of Z = S, the dual slack
//! 2 b i j v                     entry (i, j) of block b of X
//! ```
//!
//! Indices are 1-based; each symmetric entry is given once, by its upper triangle `i ≤ j` (a
//! lower-triangle entry is accepted and mirrored); entries not listed are zero; LP blocks list
//! their diagonal as entries `i = j`. The writer lists the nonzero upper-triangle entries, `S`
//! before `X` as CSDP does, with numbers in shortest round-trip form, so reading a written point
//! gives back exactly the same (symmetric) matrices.
//!
//! # Sign convention
//!
//! For a problem read with [`crate::read_sdpa`] (`C = −F_0`, `A_i = −F_i`, `b = −c`), this
//! crate's `y`, `S`, `X` are CSDP's `y`, `Z`, `X` without sign changes: CSDP solves
//! `max tr(F_0 X)` s.t. `tr(F_i X) = c_i` with dual slack `Z = Σ y_i F_i − F_0 = C − Σ y_i A_i`.
//! A CSDP solution file of an SDPA problem is therefore a point of the same problem here, and
//! the files written here can be read by CSDP's `initsoln`.
//!
//! # Errors
//!
//! The reader checks the file against the problem's layout (`m`, the block kinds and sizes)
//! and reports the first problem as a [`SolutionFileError`] naming the 1-based line; no input
//! makes it panic.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use faer::Mat;
use thiserror::Error;

use crate::problem::{BlockKind, Problem};
use crate::solver::Point;

/// A malformed or unreadable solution file.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolutionFileError {
    /// The file could not be read or written.
    #[error("I/O error: {0}")]
    Io(String),
    /// Bytes that are not UTF-8.
    #[error("line {line}: invalid UTF-8")]
    Utf8 {
        /// 1-based line of the first invalid byte.
        line: usize,
    },
    /// The first line does not hold exactly `m` numbers.
    #[error("line {line}: expected the {expected} values of y, found {found}")]
    YLength {
        /// 1-based line (always 1).
        line: usize,
        /// `m`, the number of constraints of the problem.
        expected: usize,
        /// Numbers found on the line.
        found: usize,
    },
    /// A value that is not a finite number.
    #[error("line {line}: `{token}` is not a finite number")]
    Number {
        /// 1-based line.
        line: usize,
        /// The offending token.
        token: String,
    },
    /// An entry line without exactly five fields.
    #[error("line {line}: an entry needs 5 fields `matrix block i j value`, found {found}")]
    FieldCount {
        /// 1-based line.
        line: usize,
        /// Fields found.
        found: usize,
    },
    /// A matrix number, block number or index that is not a nonnegative integer.
    #[error("line {line}: `{token}` is not a valid {what}")]
    Integer {
        /// 1-based line.
        line: usize,
        /// Which field (`"matrix number"`, `"block number"`, `"row index"`, `"column index"`).
        what: &'static str,
        /// The offending token.
        token: String,
    },
    /// A matrix number other than 1 (`Z`, the dual slack `S`) or 2 (`X`).
    #[error("line {line}: matrix number {found}, expected 1 (Z, the dual slack S) or 2 (X)")]
    Matrix {
        /// 1-based line.
        line: usize,
        /// The number found.
        found: usize,
    },
    /// A block number outside `1..=blocks`.
    #[error("line {line}: block {block} outside 1..={blocks}")]
    Block {
        /// 1-based line.
        line: usize,
        /// The block number found (1-based).
        block: usize,
        /// Number of blocks of the problem.
        blocks: usize,
    },
    /// An index outside its block.
    #[error("line {line}: entry ({i},{j}) outside block {block} of size {size}")]
    Entry {
        /// 1-based line.
        line: usize,
        /// Block (1-based).
        block: usize,
        /// Row (1-based).
        i: usize,
        /// Column (1-based).
        j: usize,
        /// Size of the block.
        size: usize,
    },
    /// An off-diagonal entry in an LP (diagonal) block.
    #[error("line {line}: off-diagonal entry ({i},{j}) in diagonal (LP) block {block}")]
    OffDiagonal {
        /// 1-based line.
        line: usize,
        /// Block (1-based).
        block: usize,
        /// Row (1-based).
        i: usize,
        /// Column (1-based).
        j: usize,
    },
    /// The same entry (up to symmetry) given twice.
    #[error(
        "line {line}: entry ({i},{j}) of block {block} of {matrix} was already given on line {first}"
    )]
    Duplicate {
        /// 1-based line of the repetition.
        line: usize,
        /// 1-based line of the first occurrence.
        first: usize,
        /// `"X"` or `"S"`.
        matrix: &'static str,
        /// Block (1-based).
        block: usize,
        /// Row (1-based).
        i: usize,
        /// Column (1-based).
        j: usize,
    },
}

impl SolutionFileError {
    /// The 1-based line the error refers to (`None` for I/O errors).
    pub fn line(&self) -> Option<usize> {
        match self {
            SolutionFileError::Io(_) => None,
            SolutionFileError::Utf8 { line }
            | SolutionFileError::YLength { line, .. }
            | SolutionFileError::Number { line, .. }
            | SolutionFileError::FieldCount { line, .. }
            | SolutionFileError::Integer { line, .. }
            | SolutionFileError::Matrix { line, .. }
            | SolutionFileError::Block { line, .. }
            | SolutionFileError::Entry { line, .. }
            | SolutionFileError::OffDiagonal { line, .. }
            | SolutionFileError::Duplicate { line, .. } => Some(*line),
        }
    }
}

/// Writes `(y, S, X)` in CSDP's solution format (see the [module documentation](self)). The
/// blocks are in the dense layout of [`crate::problem`]: a square block is written by its upper
/// triangle, an `n×1` column as the diagonal of an LP block.
pub fn write_solution(y: &[f64], x: &[Mat<f64>], s: &[Mat<f64>]) -> String {
    let mut out = String::new();
    let ys: Vec<String> = y.iter().map(|v| format!("{v:e}")).collect();
    // `fmt::Write` for `String` cannot fail.
    let _ = writeln!(out, "{}", ys.join(" "));
    for (matno, mats) in [(1, s), (2, x)] {
        for (k, m) in mats.iter().enumerate() {
            let column = m.ncols() == 1 && m.nrows() > 1;
            for j in 0..m.ncols() {
                for i in 0..m.nrows() {
                    let (r, c) = if column { (i, i) } else { (i, j) };
                    let v = m[(i, j)];
                    if (column || i <= j) && v != 0.0 {
                        let _ = writeln!(out, "{matno} {} {} {} {v:e}", k + 1, r + 1, c + 1);
                    }
                }
            }
        }
    }
    out
}

/// [`write_solution`] to a file.
pub fn write_solution_file(
    path: impl AsRef<Path>,
    y: &[f64],
    x: &[Mat<f64>],
    s: &[Mat<f64>],
) -> Result<(), SolutionFileError> {
    let path = path.as_ref();
    std::fs::write(path, write_solution(y, x, s))
        .map_err(|e| SolutionFileError::Io(format!("{}: {e}", path.display())))
}

fn integer(line: usize, what: &'static str, token: &str) -> Result<usize, SolutionFileError> {
    if token.is_empty() || !token.bytes().all(|b| b.is_ascii_digit()) {
        return Err(SolutionFileError::Integer {
            line,
            what,
            token: token.to_string(),
        });
    }
    token.parse().map_err(|_| SolutionFileError::Integer {
        line,
        what,
        token: token.to_string(),
    })
}

fn number(line: usize, token: &str) -> Result<f64, SolutionFileError> {
    match token.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(SolutionFileError::Number {
            line,
            token: token.to_string(),
        }),
    }
}

/// Reads a CSDP-format solution of `problem` (see the [module documentation](self)) into a
/// [`Point`] in the dense block layout: `y` from the first line, `S` from the entries of matrix
/// 1, `X` from those of matrix 2 (both triangles of PSD blocks filled). Blank lines after the
/// first are ignored.
pub fn read_solution(text: &str, problem: &Problem) -> Result<Point, SolutionFileError> {
    let m = problem.b.len();
    let blocks: Vec<(BlockKind, usize)> = problem
        .blocks
        .iter()
        .map(|bd| (bd.block.kind, bd.block.size))
        .collect();
    let zeros = || -> Vec<Mat<f64>> {
        blocks
            .iter()
            .map(|&(kind, n)| match kind {
                BlockKind::Psd => Mat::zeros(n, n),
                BlockKind::Lp => Mat::zeros(n, 1),
            })
            .collect()
    };
    let (mut x, mut s) = (zeros(), zeros());
    let mut lines = text.lines().enumerate().map(|(k, l)| (k + 1, l));
    let first = lines.next().map_or("", |(_, l)| l);
    let tokens: Vec<&str> = first.split_whitespace().collect();
    if tokens.len() != m {
        return Err(SolutionFileError::YLength {
            line: 1,
            expected: m,
            found: tokens.len(),
        });
    }
    let y = tokens
        .iter()
        .map(|t| number(1, t))
        .collect::<Result<Vec<f64>, _>>()?;
    let mut seen: HashMap<(usize, usize, usize, usize), usize> = HashMap::new();
    for (line, text) in lines {
        let fields: Vec<&str> = text.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        if fields.len() != 5 {
            return Err(SolutionFileError::FieldCount {
                line,
                found: fields.len(),
            });
        }
        let matno = integer(line, "matrix number", fields[0])?;
        let block = integer(line, "block number", fields[1])?;
        let i = integer(line, "row index", fields[2])?;
        let j = integer(line, "column index", fields[3])?;
        let value = number(line, fields[4])?;
        let (target, matrix) = match matno {
            1 => (&mut s, "S"),
            2 => (&mut x, "X"),
            found => return Err(SolutionFileError::Matrix { line, found }),
        };
        if block == 0 || block > blocks.len() {
            return Err(SolutionFileError::Block {
                line,
                block,
                blocks: blocks.len(),
            });
        }
        let (kind, size) = blocks[block - 1];
        if i == 0 || j == 0 || i > size || j > size {
            return Err(SolutionFileError::Entry {
                line,
                block,
                i,
                j,
                size,
            });
        }
        if kind == BlockKind::Lp && i != j {
            return Err(SolutionFileError::OffDiagonal { line, block, i, j });
        }
        let (r, c) = (i.min(j) - 1, i.max(j) - 1);
        if let Some(&first) = seen.get(&(matno, block, r, c)) {
            return Err(SolutionFileError::Duplicate {
                line,
                first,
                matrix,
                block,
                i,
                j,
            });
        }
        seen.insert((matno, block, r, c), line);
        let mat = &mut target[block - 1];
        match kind {
            BlockKind::Lp => mat[(r, 0)] = value,
            BlockKind::Psd => {
                mat[(r, c)] = value;
                mat[(c, r)] = value;
            }
        }
    }
    Ok(Point { x, y, s })
}

/// Reads and parses a solution file of `problem` ([`read_solution`]).
pub fn read_solution_file(
    path: impl AsRef<Path>,
    problem: &Problem,
) -> Result<Point, SolutionFileError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path)
        .map_err(|e| SolutionFileError::Io(format!("{}: {e}", path.display())))?;
    match String::from_utf8(bytes) {
        Ok(text) => read_solution(&text, problem),
        Err(e) => {
            let valid = e.utf8_error().valid_up_to();
            let line = 1 + e.as_bytes()[..valid]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            Err(SolutionFileError::Utf8 { line })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::ProblemBuilder;

    /// One PSD block of order 2 and one LP block of length 2, m = 2.
    fn layout() -> Problem {
        let mut pb = ProblemBuilder::new(2);
        let p = pb.add_block(BlockKind::Psd, 2);
        let l = pb.add_block(BlockKind::Lp, 2);
        pb.set_b(0, 1.0).set_b(1, 2.0);
        pb.add_a(0, p, 0, 0, 1.0).add_a(1, l, 1, 1, 1.0);
        pb.add_c(p, 0, 1, 1.0);
        pb.build().unwrap()
    }

    #[test]
    fn written_points_read_back_exactly() {
        let p = layout();
        let x = vec![
            faer::mat![[2.0, 0.1 + 0.2], [0.1 + 0.2, 1.0 / 3.0]],
            faer::mat![[1e-300], [7.0]],
        ];
        let s = vec![
            faer::mat![[1.0, 0.0], [0.0, 5.5]],
            faer::mat![[0.0], [-2.5e17]],
        ];
        let y = vec![-0.0, std::f64::consts::PI];
        let text = write_solution(&y, &x, &s);
        assert!(text.starts_with("-0e0 3.141592653589793e0\n"), "{text}");
        assert!(text.contains("\n1 2 2 2 -2.5e17\n"), "{text}");
        let back = read_solution(&text, &p).unwrap();
        assert_eq!(back, Point { x, y, s });
    }

    #[test]
    fn lower_triangle_entries_are_mirrored_and_blank_lines_skipped() {
        let p = layout();
        let text = "1 2\n\n2 1 2 1 0.5\n1 2 1 1 3\n";
        let pt = read_solution(text, &p).unwrap();
        assert_eq!(pt.x[0], faer::mat![[0.0, 0.5], [0.5, 0.0]]);
        assert_eq!(pt.s[1], faer::mat![[3.0], [0.0]]);
    }

    #[test]
    fn malformed_files_name_the_line() {
        let p = layout();
        type E = SolutionFileError;
        let cases: &[(&str, fn(&E) -> bool, usize)] = &[
            ("", |e| matches!(e, E::YLength { found: 0, .. }), 1),
            ("1 2 3\n", |e| matches!(e, E::YLength { found: 3, .. }), 1),
            ("1 x\n", |e| matches!(e, E::Number { .. }), 1),
            (
                "1 2\n2 1 1 1\n",
                |e| matches!(e, E::FieldCount { found: 4, .. }),
                2,
            ),
            ("1 2\n2 1 1 1 nan\n", |e| matches!(e, E::Number { .. }), 2),
            ("1 2\n2 1 1 1 inf\n", |e| matches!(e, E::Number { .. }), 2),
            ("1 2\n\n-2 1 1 1 1\n", |e| matches!(e, E::Integer { .. }), 3),
            (
                "1 2\n3 1 1 1 1\n",
                |e| matches!(e, E::Matrix { found: 3, .. }),
                2,
            ),
            (
                "1 2\n2 3 1 1 1\n",
                |e| matches!(e, E::Block { block: 3, .. }),
                2,
            ),
            (
                "1 2\n2 0 1 1 1\n",
                |e| matches!(e, E::Block { block: 0, .. }),
                2,
            ),
            (
                "1 2\n2 1 3 1 1\n",
                |e| matches!(e, E::Entry { i: 3, .. }),
                2,
            ),
            (
                "1 2\n2 1 0 1 1\n",
                |e| matches!(e, E::Entry { i: 0, .. }),
                2,
            ),
            (
                "1 2\n2 2 1 2 1\n",
                |e| matches!(e, E::OffDiagonal { .. }),
                2,
            ),
            (
                "1 2\n2 1 1 2 1\n1 1 1 2 1\n2 1 2 1 1\n",
                |e| {
                    matches!(
                        e,
                        E::Duplicate {
                            first: 2,
                            matrix: "X",
                            ..
                        }
                    )
                },
                4,
            ),
            ("1 2\n2 1 1 1 1e999\n", |e| matches!(e, E::Number { .. }), 2),
            (
                "1 2\n2 99999999999999999999999 1 1 1\n",
                |e| matches!(e, E::Integer { .. }),
                2,
            ),
        ];
        for &(text, is, line) in cases {
            match read_solution(text, &p) {
                Err(e) => {
                    assert!(is(&e), "{text:?}: {e:?}");
                    assert_eq!(e.line(), Some(line), "{text:?}: {e}");
                    assert!(e.to_string().contains(&format!("line {line}")), "{e}");
                }
                Ok(pt) => panic!("{text:?}: expected an error, got {pt:?}"),
            }
        }
    }

    #[test]
    fn files_round_trip_and_report_io_errors() {
        let p = layout();
        let dir = std::env::temp_dir().join(format!("sporadic-solfile-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("pt.sol");
        let (x, s) = (
            vec![faer::mat![[1.0, 0.0], [0.0, 1.0]], faer::mat![[1.0], [2.0]]],
            vec![faer::mat![[3.0, 1.0], [1.0, 3.0]], faer::mat![[4.0], [5.0]]],
        );
        write_solution_file(&path, &[1.0, -1.0], &x, &s).unwrap();
        let pt = read_solution_file(&path, &p).unwrap();
        assert_eq!((pt.x, pt.s), (x, s));
        std::fs::write(&path, b"1 2\n2 1 1 1 \xff\n").unwrap();
        assert_eq!(
            read_solution_file(&path, &p),
            Err(SolutionFileError::Utf8 { line: 2 })
        );
        assert!(matches!(
            read_solution_file(dir.join("missing.sol"), &p),
            Err(SolutionFileError::Io(_))
        ));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
