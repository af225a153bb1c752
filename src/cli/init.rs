//! `sporadic init`: writes a commented plant-file template (the format of
//! `sporadic::plant_file`), so the format is reachable from the binary.

use super::{Failure, Outcome};
use std::io::Write;
use std::path::PathBuf;

/// Which template.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum Kind {
    /// A linear plant with one sampling window.
    Linear,
    /// Sensors polled round-robin, each with its own window.
    RoundRobin,
    /// A plant with a Lipschitz nonlinearity (Jacobian bounds).
    Lipschitz,
    /// A linear plant with disturbance and noise bounds (interval observer).
    Bounds,
}

/// Arguments of `sporadic init`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The kind of plant.
    #[arg(long, value_enum, default_value = "linear")]
    pub kind: Kind,
    /// Write the template to this file (refuses to overwrite); default: standard output.
    pub file: Option<PathBuf>,
}

/// The template text of `kind`; each parses as a valid plant file (tested).
pub fn template(kind: Kind) -> &'static str {
    match kind {
        Kind::Linear => include_str!("templates/linear.toml"),
        Kind::RoundRobin => include_str!("templates/round-robin.toml"),
        Kind::Lipschitz => include_str!("templates/lipschitz.toml"),
        Kind::Bounds => include_str!("templates/bounds.toml"),
    }
}

/// Runs `sporadic init`.
pub fn run(args: &Args) -> Result<Outcome, Failure> {
    let text = template(args.kind);
    match &args.file {
        None => print!("{text}"),
        Some(path) => {
            let mut f = std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(path)
                .map_err(|e| Failure::Input(format!("{}: {e}", path.display())))?;
            f.write_all(text.as_bytes())
                .map_err(|e| Failure::Input(format!("{}: {e}", path.display())))?;
            eprintln!("wrote {}", path.display());
        }
    }
    Ok(Outcome::Certified)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sporadic::plant_file::PlantFile;
    use std::path::Path;

    #[test]
    fn every_template_is_a_valid_plant_file() {
        for kind in [
            Kind::Linear,
            Kind::RoundRobin,
            Kind::Lipschitz,
            Kind::Bounds,
        ] {
            let p = PlantFile::parse(template(kind), Path::new("template.toml"))
                .unwrap_or_else(|e| panic!("{kind:?}: {e}"));
            assert!(!p.setups().is_empty(), "{kind:?}");
        }
    }
}
