//! Two observer methods side by side on one plant of our own, through the facade only, as an
//! outside crate would use it (`sporadic = { path = "...", default-features = false }`):
//! a lightly damped oscillator `ÿ + 0.2ẏ + y = 0` with its position measured at sampling
//! intervals anywhere in `[0.1, 0.6]`.
//!
//! Run with `cargo run --release --example two_methods`.

use sporadic::faer::mat;
use sporadic::{MethodOptions, ObserverMethod, Plant, Sampling, SamplingWindow};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let plant = Plant::linear(
        mat![[0.0, 1.0], [-1.0, -0.2]].as_ref(),
        None,
        mat![[1.0, 0.0]].as_ref(),
    )?
    .named("lightly damped oscillator");
    let sampling = Sampling::Synchronous(SamplingWindow::new(0.1, 0.6)?);
    let ferrante = sporadic::Ferrante2016::default();
    let sferlazza = sporadic::Sferlazza2021::default();
    let methods: [&dyn ObserverMethod; 2] = [&ferrante, &sferlazza];
    for method in methods {
        let report = method.design(&plant, &sampling, &MethodOptions::default())?;
        println!("{}: {}", method.id(), report.status);
        if let Some(reason) = &report.reason {
            println!("  reason: {reason}");
        }
        for gain in &report.gains {
            println!("  {} = {:?}", gain.name, gain.rows);
            println!("    ({})", gain.meaning);
        }
        if let Some(m) = &report.margin {
            println!("  margin {:.3e}: {}", m.value, m.definition);
        }
        let search = method.largest_window(
            &plant,
            &sampling,
            3.0,
            &MethodOptions::default(),
            &mut |_| {},
        )?;
        println!(
            "  largest certified T2 with T1 = 0.1: {:?} (first failing: {:?})",
            search.largest_certified_t2, search.first_failing_t2
        );
    }
    Ok(())
}
