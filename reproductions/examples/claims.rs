//! Prints the checked claims of one paper's reproduction as JSON lines (the format of
//! `sporadic reproduce <paper> --json` without the figure lines), for comparing two builds.
//! Usage: `cargo run --release -p sporadic-reproductions --example claims -- <paper> [out_dir]`.

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let id = std::env::args()
        .nth(1)
        .ok_or("usage: claims <paper> [out_dir]")?;
    let out = std::env::args()
        .nth(2)
        .unwrap_or_else(|| "target/claims".into());
    let paper = sporadic_reproductions::PAPERS
        .iter()
        .find(|p| p.id == id)
        .ok_or_else(|| format!("unknown paper {}", &id))?;
    let r = (paper.run)(&std::path::Path::new(&out).join(&id))?;
    for c in &r.claims {
        println!("{}", c.to_json(&id));
    }
    Ok(())
}
