//! Every figure function writes a well-formed SVG with the expected elements (parsed back as XML).

use std::path::PathBuf;

use faer::mat;
use sporadic_figures::{
    PlotSpec, Series, is_distrusted_label, plot_components, plot_eigen_curves, plot_error_norm,
    plot_hybrid_time, plot_interval_bounds,
};
use sporadic_sim::{
    LinearJump, LtiFlow, Periodic, Record, SimOptions, Simulation, simulate_hybrid,
};

fn out_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sporadic-figures-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn oscillator_run() -> Simulation {
    let flow = LtiFlow::new(mat![[0.0, 1.0], [-4.0, -0.2]].as_ref()).unwrap();
    let jump = LinearJump::new(mat![[0.3, 0.0], [0.0, 0.8]]).unwrap();
    let opts = SimOptions::new(6.0).record(Record::Every(0.02));
    simulate_hybrid(
        flow,
        jump,
        &mut Periodic::new(1.5).unwrap(),
        &[1.0, 0.5],
        &opts,
    )
    .unwrap()
}

struct Svg {
    text: String,
}

impl Svg {
    fn read(path: &std::path::Path) -> Self {
        Self {
            text: std::fs::read_to_string(path).unwrap(),
        }
    }

    fn check(&self, title: &str, min_polylines: usize) -> roxmltree::Document<'_> {
        let doc = roxmltree::Document::parse(&self.text).expect("well-formed XML");
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "svg");
        assert!(root.attribute("width").is_some() && root.attribute("height").is_some());
        let texts: Vec<String> = doc
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .map(|n| n.descendants().filter_map(|c| c.text()).collect::<String>())
            .collect();
        assert!(
            texts.iter().any(|t| t.contains(title)),
            "title {title:?} missing from {texts:?}"
        );
        let polylines = doc
            .descendants()
            .filter(|n| n.has_tag_name("polyline"))
            .count();
        assert!(
            polylines >= min_polylines,
            "{polylines} polylines < {min_polylines}"
        );
        doc
    }
}

fn count(doc: &roxmltree::Document<'_>, tag: &str) -> usize {
    doc.descendants().filter(|n| n.has_tag_name(tag)).count()
}

#[test]
fn all_figures_are_valid_svg() {
    let dir = out_dir("figures");
    let sim = oscillator_run();
    let (t, j) = (sim.arc.times(), sim.arc.jump_counters());
    let x0 = sim.arc.component(0).unwrap();
    let x1 = sim.arc.component(1).unwrap();
    let norms = sim.arc.norms();
    let jumps = sim.arc.num_jumps();
    assert_eq!(jumps, 4);

    // Error norm with a bound, log scale. Flows: jumps + 1 polylines for the norm (plus legend/bound).
    let bound: Vec<f64> = t.iter().map(|s| 2.0 * (-0.3 * s).exp()).collect();
    let spec = PlotSpec::new("Error norm", "time t", "|e|").log_y();
    let p = dir.join("norm.svg");
    plot_error_norm(
        &p,
        &spec,
        t,
        j,
        &norms,
        Some(Series {
            label: "bound",
            x: t,
            y: &bound,
        }),
    )
    .unwrap();
    let svg = Svg::read(&p);
    let doc = svg.check("Error norm", jumps + 1);
    assert!(
        svg.text.contains("bound") && svg.text.contains("error norm"),
        "legend entries"
    );
    let _ = doc;

    let spec = PlotSpec::new("Components", "time t", "x");
    let p = dir.join("components.svg");
    plot_components(&p, &spec, t, j, &[("x1", &x0), ("x2", &x1)]).unwrap();
    Svg::read(&p).check("Components", 2 * (jumps + 1));

    let lower: Vec<f64> = x0.iter().map(|v| v - 0.5).collect();
    let upper: Vec<f64> = x0.iter().map(|v| v + 0.5).collect();
    let spec = PlotSpec::new("Interval bounds", "time t", "x1");
    let p = dir.join("bounds.svg");
    plot_interval_bounds(&p, &spec, t, j, &lower, &upper, &x0).unwrap();
    let svg = Svg::read(&p);
    let doc = svg.check("Interval bounds", 3 * (jumps + 1));
    assert_eq!(
        count(&doc, "polygon"),
        jumps + 1,
        "one shaded band per flow interval"
    );

    let tau: Vec<f64> = (0..=100).map(|k| 0.02 + 0.0005 * k as f64).collect();
    let lam: Vec<f64> = tau.iter().map(|s| (30.0 * s).sin()).collect();
    let spec = PlotSpec::new("Eigenvalue curves", "tau", "lambda_min");
    let p = dir.join("eig.svg");
    plot_eigen_curves(
        &p,
        &spec,
        &[Series {
            label: "sigma = 1",
            x: &tau,
            y: &lam,
        }],
    )
    .unwrap();
    Svg::read(&p).check("Eigenvalue curves", 1);

    let spec = PlotSpec::new("Hybrid arc", "time t", "x1");
    let p = dir.join("hybrid.svg");
    plot_hybrid_time(&p, &spec, t, j, &[("x1", &x0)]).unwrap();
    let svg = Svg::read(&p);
    let doc = svg.check("Hybrid arc (vs j)", 2 * (jumps + 1));
    assert!(svg.text.contains("Hybrid arc (vs t)"));
    assert_eq!(
        count(&doc, "circle"),
        jumps + 1,
        "one marker per post-jump value in the j panel"
    );

    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn figure_inputs_are_validated() {
    let dir = out_dir("invalid-figures");
    let spec = PlotSpec::new("x", "t", "y");
    let p = dir.join("bad.svg");
    assert!(plot_error_norm(&p, &spec, &[0.0, 1.0], &[0, 0], &[1.0], None).is_err());
    assert!(plot_error_norm(&p, &spec, &[0.0, 1.0], &[0], &[1.0, 2.0], None).is_err());
    assert!(plot_error_norm(&p, &spec, &[], &[], &[], None).is_err());
    assert!(plot_components(&p, &spec, &[0.0, 1.0], &[0, 0], &[("a", &[1.0, f64::NAN])]).is_err());
    assert!(plot_components(&p, &spec, &[0.0], &[0], &[]).is_err());
    assert!(plot_eigen_curves(&p, &spec, &[]).is_err());
    // An unwritable path is an error, not a panic.
    let missing = dir.join("no/such/dir/f.svg");
    assert!(plot_components(&missing, &spec, &[0.0, 1.0], &[0, 0], &[("a", &[1.0, 2.0])]).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The text of every `<text>` element of an SVG file.
fn svg_texts(path: &std::path::Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.descendants().filter_map(|c| c.text()).collect::<String>())
        .collect()
}

#[test]
fn tick_labels_are_readable_on_log_and_linear_axes() {
    let dir = out_dir("ticks");
    // Log axis over many decades (the ferrante2016 Fig. 2 case) and a linear axis whose range
    // straddles zero (the etienne2017 Fig. 1 case).
    let t: Vec<f64> = (0..=600).map(|i| f64::from(i) * 0.1).collect();
    let j: Vec<usize> = (0..t.len()).map(|i| i / 20).collect();
    let decay: Vec<f64> = t.iter().map(|&t| (-0.6 * t).exp()).collect();
    let wave: Vec<f64> = t
        .iter()
        .map(|&t| 0.3 * (t).sin() * (-0.1 * t).exp())
        .collect();
    let log = dir.join("log.svg");
    plot_hybrid_time(
        &log,
        &PlotSpec::new("log", "t", "squared error").log_y(),
        &t,
        &j,
        &[("e", &decay)],
    )
    .unwrap();
    let lin = dir.join("lin.svg");
    plot_components(
        &lin,
        &PlotSpec::new("lin", "t", "z"),
        &t,
        &j,
        &[("z", &wave)],
    )
    .unwrap();
    for path in [&log, &lin] {
        let texts = svg_texts(path);
        assert!(texts.len() > 8, "{texts:?}");
        for label in &texts {
            assert!(!is_distrusted_label(label), "{}: {label:?}", path.display());
        }
    }
    assert!(
        svg_texts(&log).iter().any(|l| l.contains("1e-")),
        "powers of ten"
    );
    assert!(
        is_distrusted_label("9.999999999999999e-5")
            && is_distrusted_label("-0.0")
            && is_distrusted_label("-0")
    );
    assert!(!is_distrusted_label("-0.5") && !is_distrusted_label("1e-5"));
    std::fs::remove_dir_all(&dir).unwrap();
}
