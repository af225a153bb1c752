//! Plant files: a user's plant and sensor timing in TOML, validated before any design runs.
//!
//! ```toml
//! name = "mass-spring, one position sensor"
//!
//! [plant]
//! A = [[0.0, 1.0], [-2.0, -0.3]]   # n×n state matrix (required)
//! B = [[0.0], [1.0]]                # n×m input matrix (optional)
//! C = [[1.0, 0.0]]                  # p×n output matrix (required unless [[sensors]] is given)
//!
//! [sampling]
//! window = [0.05, 0.4]              # every sampling interval τ_k lies in [T1, T2], 0 < T1 ≤ T2
//!
//! [[sensors]]                       # optional: round-robin sensors, polled in this order
//! C = [[1.0, 0.0]]                  # (Sferlazza et al. 2021); each has its own window
//! window = [0.02, 0.07]
//!
//! [lipschitz]                       # optional: ẋ = Ax + Bu + Gφ(Hx) with
//! G = [[0.0], [1.0]]                # ∂φ_i/∂v_j ∈ [lower_ij, upper_ij] (Etienne et al. 2017)
//! H = [[1.0, 0.0]]
//! jacobian_lower = [[-0.5]]
//! jacobian_upper = [[0.5]]
//!
//! [bounds]                          # optional: |w_i| ≤ disturbance_i, |v_j| ≤ noise_j
//! disturbance = [0.01, 0.01]        # (interval observer of Rabehi et al. 2021)
//! noise = [0.001]
//! ```
//!
//! Every matrix is a list of rows. [`PlantFile::parse`] checks the TOML syntax, unknown keys,
//! shapes (square `A`, `B` and `C` conformal with `A`, rectangular rows), finiteness and the
//! windows, and reports the first problem with the file's name, the line, and the field.

use faer::Mat;
use serde::Deserialize;
use sporadic_model::{
    Bounds as ModelBounds, Lipschitz as ModelLipschitz, Plant, Sampling, SamplingWindow,
};
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// What was wrong with a plant file, and where.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{}: {field}: {message}", path.display(), line_suffix(*line))]
pub struct PlantFileError {
    /// The file (as given by the user).
    pub path: PathBuf,
    /// 1-based line of the offending value (or of the section that lacks a field); 0 when the
    /// error concerns the whole file (e.g. it cannot be read).
    pub line: usize,
    /// The field, e.g. `plant.A` or `sensors[1].window`.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

/// `:line` for a line in the file, nothing for the whole file.
fn line_suffix(line: usize) -> String {
    if line == 0 {
        String::new()
    } else {
        format!(":{line}")
    }
}

/// One round-robin sensor: its output matrix and its own sampling window.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensor {
    /// Output matrix `C_σ` (`p_σ × n`).
    pub c: Mat<f64>,
    /// Window of the interval that ends with this sensor's sample.
    pub window: SamplingWindow,
}

/// The Lipschitz nonlinearity `Gφ(Hx)` with elementwise bounds on the Jacobian of `φ`.
#[derive(Debug, Clone, PartialEq)]
pub struct Lipschitz {
    /// `G` (`n × q`).
    pub g: Mat<f64>,
    /// `H` (`r × n`).
    pub h: Mat<f64>,
    /// Lower bounds on `∂φ_i/∂v_j` (`q × r`).
    pub jacobian_lower: Mat<f64>,
    /// Upper bounds on `∂φ_i/∂v_j` (`q × r`), elementwise `≥` the lower ones.
    pub jacobian_upper: Mat<f64>,
}

/// Bounds on the disturbance and the measurement noise.
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds {
    /// `|w_i| ≤ disturbance_i` (one per state, or empty).
    pub disturbance: Vec<f64>,
    /// `|v_j| ≤ noise_j` (one per output, or empty).
    pub noise: Vec<f64>,
}

/// A validated plant file.
#[derive(Debug, Clone, PartialEq)]
pub struct PlantFile {
    /// Free-text name.
    pub name: String,
    /// State matrix `A` (`n × n`).
    pub a: Mat<f64>,
    /// Input matrix `B` (`n × m`), if given.
    pub b: Option<Mat<f64>>,
    /// Output matrix `C` (`p × n`), if given.
    pub c: Option<Mat<f64>>,
    /// Sampling window of the single-sensor methods, if given.
    pub window: Option<SamplingWindow>,
    /// Round-robin sensors in polling order (empty if none).
    pub sensors: Vec<Sensor>,
    /// Lipschitz nonlinearity, if any.
    pub lipschitz: Option<Lipschitz>,
    /// Disturbance and noise bounds, if any.
    pub bounds: Option<Bounds>,
}

type Rows = Spanned<Vec<Vec<f64>>>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    name: Option<String>,
    plant: Spanned<RawPlant>,
    sampling: Option<RawSampling>,
    #[serde(default)]
    sensors: Vec<Spanned<RawSensor>>,
    lipschitz: Option<Spanned<RawLipschitz>>,
    bounds: Option<RawBounds>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPlant {
    #[serde(rename = "A")]
    a: Rows,
    #[serde(rename = "B")]
    b: Option<Rows>,
    #[serde(rename = "C")]
    c: Option<Rows>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSampling {
    window: Spanned<Vec<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSensor {
    #[serde(rename = "C")]
    c: Rows,
    window: Spanned<Vec<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLipschitz {
    #[serde(rename = "G")]
    g: Rows,
    #[serde(rename = "H")]
    h: Rows,
    jacobian_lower: Rows,
    jacobian_upper: Rows,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBounds {
    disturbance: Option<Spanned<Vec<f64>>>,
    noise: Option<Spanned<Vec<f64>>>,
}

/// Error factory bound to one file's text.
struct Ctx<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Ctx<'_> {
    fn line(&self, span: Range<usize>) -> usize {
        let end = span.start.min(self.text.len());
        self.text[..end].bytes().filter(|&b| b == b'\n').count() + 1
    }

    fn err(&self, span: Range<usize>, field: &str, message: impl Into<String>) -> PlantFileError {
        PlantFileError {
            path: self.path.to_path_buf(),
            line: self.line(span),
            field: field.to_string(),
            message: message.into(),
        }
    }

    /// A finite matrix with rows of equal length and the given shape constraints.
    fn matrix(
        &self,
        rows: &Rows,
        field: &str,
        nrows: Option<usize>,
        ncols: Option<usize>,
    ) -> Result<Mat<f64>, PlantFileError> {
        let span = rows.span();
        let r = rows.get_ref();
        if r.is_empty() || r[0].is_empty() {
            return Err(self.err(span, field, "empty matrix"));
        }
        let cols = r[0].len();
        if let Some((i, row)) = r.iter().enumerate().find(|(_, row)| row.len() != cols) {
            return Err(self.err(
                span,
                field,
                format!(
                    "row {} has {} entries but row 1 has {cols}",
                    i + 1,
                    row.len()
                ),
            ));
        }
        for (i, row) in r.iter().enumerate() {
            if let Some(j) = row.iter().position(|x| !x.is_finite()) {
                return Err(self.err(
                    span,
                    field,
                    format!("entry ({}, {}) is not finite", i + 1, j + 1),
                ));
            }
        }
        if let Some(n) = nrows.filter(|&n| n != r.len()) {
            return Err(self.err(span, field, format!("has {} rows, expected {n}", r.len())));
        }
        if let Some(n) = ncols.filter(|&n| n != cols) {
            return Err(self.err(span, field, format!("has {cols} columns, expected {n}")));
        }
        Ok(Mat::from_fn(r.len(), cols, |i, j| r[i][j]))
    }

    fn window(&self, w: &Spanned<Vec<f64>>, field: &str) -> Result<SamplingWindow, PlantFileError> {
        let span = w.span();
        let &[t1, t2] = w.get_ref().as_slice() else {
            return Err(self.err(span, field, "expected two numbers [T1, T2]"));
        };
        if !t1.is_finite() || !t2.is_finite() {
            return Err(self.err(span, field, "T1 and T2 must be finite"));
        }
        if t1 <= 0.0 {
            return Err(self.err(span, field, format!("T1 = {t1} must be positive")));
        }
        if t1 > t2 {
            return Err(self.err(span, field, format!("T1 = {t1} exceeds T2 = {t2}")));
        }
        SamplingWindow::new(t1, t2).map_err(|e| self.err(span, field, e.to_string()))
    }

    fn bound_vector(
        &self,
        v: Option<&Spanned<Vec<f64>>>,
        field: &str,
        len: usize,
    ) -> Result<Vec<f64>, PlantFileError> {
        let Some(v) = v else {
            return Ok(Vec::new());
        };
        let x = v.get_ref();
        if x.len() != len {
            return Err(self.err(
                v.span(),
                field,
                format!("has {} entries, expected {len}", x.len()),
            ));
        }
        if let Some(i) = x.iter().position(|b| !(b.is_finite() && *b >= 0.0)) {
            return Err(self.err(
                v.span(),
                field,
                format!("entry {} must be finite and non-negative", i + 1),
            ));
        }
        Ok(x.clone())
    }
}

impl PlantFile {
    /// Reads and validates a plant file.
    pub fn read(path: &Path) -> Result<Self, PlantFileError> {
        let text = std::fs::read_to_string(path).map_err(|e| PlantFileError {
            path: path.to_path_buf(),
            line: 0,
            field: "file".into(),
            message: e.to_string(),
        })?;
        Self::parse(&text, path)
    }

    /// Validates the text of a plant file; `path` is only used in error messages.
    pub fn parse(text: &str, path: &Path) -> Result<Self, PlantFileError> {
        let cx = Ctx { path, text };
        let raw: RawFile = toml::from_str(text).map_err(|e| {
            let span = e.span().unwrap_or(0..0);
            cx.err(span, "toml", e.message().trim_end())
        })?;
        let plant = raw.plant.get_ref();
        let a = cx.matrix(&plant.a, "plant.A", None, None)?;
        let n = a.nrows();
        if a.ncols() != n {
            return Err(cx.err(
                plant.a.span(),
                "plant.A",
                format!("must be square, is {n}×{}", a.ncols()),
            ));
        }
        let b = plant
            .b
            .as_ref()
            .map(|b| cx.matrix(b, "plant.B", Some(n), None))
            .transpose()?;
        let c = plant
            .c
            .as_ref()
            .map(|c| cx.matrix(c, "plant.C", None, Some(n)))
            .transpose()?;
        let window = raw
            .sampling
            .as_ref()
            .map(|s| cx.window(&s.window, "sampling.window"))
            .transpose()?;
        let sensors = raw
            .sensors
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let s = s.get_ref();
                Ok(Sensor {
                    c: cx.matrix(&s.c, &format!("sensors[{i}].C"), None, Some(n))?,
                    window: cx.window(&s.window, &format!("sensors[{i}].window"))?,
                })
            })
            .collect::<Result<Vec<_>, PlantFileError>>()?;
        if c.is_none() && sensors.is_empty() {
            return Err(cx.err(
                raw.plant.span(),
                "plant.C",
                "missing: give plant.C or at least one [[sensors]] entry",
            ));
        }
        let lipschitz = raw
            .lipschitz
            .as_ref()
            .map(|l| {
                let span = l.span();
                let l = l.get_ref();
                let g = cx.matrix(&l.g, "lipschitz.G", Some(n), None)?;
                let h = cx.matrix(&l.h, "lipschitz.H", None, Some(n))?;
                let (q, r) = (g.ncols(), h.nrows());
                let lo = cx.matrix(
                    &l.jacobian_lower,
                    "lipschitz.jacobian_lower",
                    Some(q),
                    Some(r),
                )?;
                let hi = cx.matrix(
                    &l.jacobian_upper,
                    "lipschitz.jacobian_upper",
                    Some(q),
                    Some(r),
                )?;
                for i in 0..q {
                    for j in 0..r {
                        if lo[(i, j)] > hi[(i, j)] {
                            return Err(cx.err(
                                span.clone(),
                                "lipschitz.jacobian_lower",
                                format!(
                                    "entry ({}, {}) = {} exceeds the upper bound {}",
                                    i + 1,
                                    j + 1,
                                    lo[(i, j)],
                                    hi[(i, j)]
                                ),
                            ));
                        }
                    }
                }
                Ok(Lipschitz {
                    g,
                    h,
                    jacobian_lower: lo,
                    jacobian_upper: hi,
                })
            })
            .transpose()?;
        let outputs = c.as_ref().map_or(0, |c| c.nrows());
        let bounds = raw
            .bounds
            .as_ref()
            .map(|bd| {
                Ok::<_, PlantFileError>(Bounds {
                    disturbance: cx.bound_vector(
                        bd.disturbance.as_ref(),
                        "bounds.disturbance",
                        n,
                    )?,
                    noise: cx.bound_vector(bd.noise.as_ref(), "bounds.noise", outputs)?,
                })
            })
            .transpose()?;
        Ok(Self {
            name: raw.name.unwrap_or_else(|| path.display().to_string()),
            a,
            b,
            c,
            window,
            sensors,
            lipschitz,
            bounds,
        })
    }

    /// The plant file of a validated plant and its sampling (the inverse of [`PlantFile::setups`]
    /// for one setup): lets a program build what a TOML file would give.
    pub fn from_plant(plant: &Plant, sampling: &Sampling) -> Self {
        use sporadic_model::Outputs;
        let (c, window, sensors) = match (plant.output_structure(), sampling) {
            (Outputs::Synchronous(c), Sampling::Synchronous(w)) => {
                (Some(c.clone()), Some(*w), vec![])
            }
            (Outputs::Synchronous(c), Sampling::RoundRobin(ws)) => (
                Some(c.clone()),
                None,
                ws.iter()
                    .map(|w| Sensor {
                        c: c.clone(),
                        window: *w,
                    })
                    .collect(),
            ),
            (Outputs::RoundRobin(cs), s) => (
                None,
                None,
                cs.iter()
                    .zip(s.windows().iter().cycle())
                    .map(|(c, w)| Sensor {
                        c: c.clone(),
                        window: *w,
                    })
                    .collect(),
            ),
        };
        Self {
            name: plant.name().to_string(),
            a: plant.a().to_owned(),
            b: (plant.b().ncols() > 0).then(|| plant.b().to_owned()),
            c,
            window,
            sensors,
            lipschitz: plant.lipschitz().map(|l| Lipschitz {
                g: l.g().to_owned(),
                h: l.h().to_owned(),
                jacobian_lower: l.jacobian_lower().to_owned(),
                jacobian_upper: l.jacobian_upper().to_owned(),
            }),
            bounds: plant.bounds().map(|b| Bounds {
                disturbance: b.disturbance().to_vec(),
                noise: b.noise().to_vec(),
            }),
        }
    }

    /// State dimension `n`.
    pub fn n(&self) -> usize {
        self.a.nrows()
    }

    /// The plant with all its outputs sampled at once (`plant.C` and `[sampling] window`), if
    /// the file gives both.
    pub fn synchronous(&self) -> Option<(Plant, Sampling)> {
        let (c, w) = (self.c.as_ref()?, self.window?);
        let plant = Plant::linear(
            self.a.as_ref(),
            self.b.as_ref().map(|b| b.as_ref()),
            c.as_ref(),
        )
        .ok()?;
        Some((self.decorate(plant), Sampling::Synchronous(w)))
    }

    /// The plant with its `[[sensors]]` polled round-robin, if the file has sensors.
    pub fn round_robin(&self) -> Option<(Plant, Sampling)> {
        if self.sensors.is_empty() {
            return None;
        }
        let cs: Vec<_> = self.sensors.iter().map(|s| s.c.as_ref()).collect();
        let plant =
            Plant::round_robin(self.a.as_ref(), self.b.as_ref().map(|b| b.as_ref()), &cs).ok()?;
        let windows = self.sensors.iter().map(|s| s.window).collect();
        Some((self.decorate(plant), Sampling::RoundRobin(windows)))
    }

    /// The sampling setups the file describes, round-robin first: a method is run on the
    /// first one it applies to.
    pub fn setups(&self) -> Vec<(Plant, Sampling)> {
        self.round_robin()
            .into_iter()
            .chain(self.synchronous())
            .collect()
    }

    /// The file's name, Lipschitz data and bounds added to `plant` (bounds that do not fit the
    /// plant's outputs, e.g. per-`C` noise bounds on round-robin sensors, are left out).
    fn decorate(&self, plant: Plant) -> Plant {
        let mut plant = plant.named(self.name.clone());
        if let Some(l) = &self.lipschitz
            && let Ok(lip) = ModelLipschitz::new(
                l.g.as_ref(),
                l.h.as_ref(),
                l.jacobian_lower.as_ref(),
                l.jacobian_upper.as_ref(),
            )
            && let Ok(p) = plant.clone().with_lipschitz(lip)
        {
            plant = p;
        }
        if let Some(b) = &self.bounds
            && let Ok(bounds) = ModelBounds::new(b.disturbance.clone(), b.noise.clone())
            && let Ok(p) = plant.clone().with_bounds(bounds)
        {
            plant = p;
        }
        plant
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<PlantFile, PlantFileError> {
        PlantFile::parse(text, Path::new("plant.toml"))
    }

    const GOOD: &str = r#"
name = "oscillator"
[plant]
A = [[0.0, 1.0], [-1.0, 0.0]]
C = [[1.0, 0.0]]
[sampling]
window = [0.1, 0.5]
"#;

    #[test]
    fn a_valid_file_is_read() {
        let p = parse(GOOD).unwrap();
        assert_eq!(p.name, "oscillator");
        assert_eq!(p.n(), 2);
        assert_eq!(p.a[(1, 0)], -1.0);
        assert_eq!(p.window, Some(SamplingWindow::new(0.1, 0.5).unwrap()));
        assert!(p.sensors.is_empty() && p.lipschitz.is_none() && p.b.is_none());
    }

    #[test]
    fn errors_name_the_field_and_line() {
        let e = parse(&GOOD.replace("[0.1, 0.5]", "[0.5, 0.1]")).unwrap_err();
        assert_eq!((e.field.as_str(), e.line), ("sampling.window", 7));
        assert!(e.message.contains("exceeds"), "{e}");
        let e = parse(&GOOD.replace("[0.1, 0.5]", "[0.0, 0.1]")).unwrap_err();
        assert!(e.message.contains("positive"), "{e}");
        let e = parse(&GOOD.replace("C = [[1.0, 0.0]]", "C = [[1.0, 0.0, 2.0]]")).unwrap_err();
        assert_eq!((e.field.as_str(), e.line), ("plant.C", 5));
        let e = parse(&GOOD.replace("[-1.0, 0.0]]", "[-1.0]]")).unwrap_err();
        assert_eq!(e.field, "plant.A");
        assert!(e.message.contains("row 2"), "{e}");
        let e = parse(&GOOD.replace("[-1.0, 0.0]]", "[-1.0, 0.0], [1.0, 1.0]]")).unwrap_err();
        assert!(e.message.contains("square"), "{e}");
        assert_eq!(
            e.to_string(),
            "plant.toml:4: plant.A: must be square, is 3×2"
        );
    }

    #[test]
    fn syntax_errors_and_unknown_keys_are_reported_with_a_line() {
        let e = parse(&GOOD.replace("window =", "widnow =")).unwrap_err();
        assert_eq!((e.field.as_str(), e.line), ("toml", 7));
        assert!(e.message.contains("widnow"), "{e}");
        let e = parse(&GOOD.replace("[[1.0, 0.0]]", "[[1.0, 0.0]")).unwrap_err();
        assert_eq!(e.field, "toml");
        assert!(e.line >= 5, "{e}");
        let e = parse("[plant]\nA = [[nan]]\nC = [[1.0]]\n").unwrap_err();
        assert!(e.message.contains("not finite"), "{e}");
    }

    #[test]
    fn the_shipped_example_files_are_valid() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
        let mut count = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                let p = PlantFile::read(&path).unwrap_or_else(|e| panic!("{e}"));
                assert!(p.window.is_some() || !p.sensors.is_empty(), "{}", p.name);
                count += 1;
            }
        }
        assert!(count >= 6, "{count} example files");
        let s = PlantFile::read(&dir.join("sferlazza2021-suspension.toml")).unwrap();
        assert_eq!(
            s.sensors[1].window,
            SamplingWindow::new(0.04, 0.09).unwrap()
        );
        assert_eq!(s.a[(3, 0)], 1.6e4 / 45.0);
    }

    #[test]
    fn a_missing_output_matrix_is_an_error() {
        let e = parse("[plant]\nA = [[1.0]]\n").unwrap_err();
        assert_eq!(e.field, "plant.C");
    }

    #[test]
    fn sensors_lipschitz_and_bounds() {
        let text = r#"
[plant]
A = [[0.0, 1.0], [0.0, 0.0]]
[[sensors]]
C = [[1.0, 0.0]]
window = [0.01, 0.02]
[[sensors]]
C = [[0.0, 1.0]]
window = [0.03, 0.03]
[lipschitz]
G = [[0.0], [1.0]]
H = [[1.0, 0.0]]
jacobian_lower = [[-1.0]]
jacobian_upper = [[1.0]]
[bounds]
disturbance = [0.1, 0.2]
"#;
        let p = parse(text).unwrap();
        assert_eq!(p.sensors.len(), 2);
        assert_eq!(p.sensors[1].window.t1(), 0.03);
        assert_eq!(p.lipschitz.as_ref().unwrap().h.ncols(), 2);
        assert_eq!(p.bounds.as_ref().unwrap().disturbance, vec![0.1, 0.2]);
        let e = parse(&text.replace("jacobian_upper = [[1.0]]", "jacobian_upper = [[-2.0]]"))
            .unwrap_err();
        assert_eq!(e.field, "lipschitz.jacobian_lower");
        let e = parse(&text.replace("window = [0.03, 0.03]", "window = [0.03]")).unwrap_err();
        assert_eq!((e.field.as_str(), e.line), ("sensors[1].window", 9));
        let e = parse(&text.replace("[0.1, 0.2]", "[0.1, -0.2]")).unwrap_err();
        assert!(e.message.contains("non-negative"), "{e}");
    }
}
