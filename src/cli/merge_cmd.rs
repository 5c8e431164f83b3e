//! `prism merge PART.prism-film ... -o OUT.exr [-o OUT.png] [-o OUT.prism-film]`: combine the shards of one render.
//!
//! Every part must come from the same scene and settings (equal fingerprints, sizes, integrators and shard counts),
//! and together they must be shards `0..N` exactly once. Films add exactly (fixed-point sums), so the merged image
//! equals the one-process render of the same scene, seed and total bit for bit. A missing or incomplete shard is an
//! error unless `--partial` is given (the image is then the mean of the samples that exist).

use clap::Args;
use prism_core::error::PrismError;
use prism_core::film::{ShardAxis, read_film, write_film};
use prism_core::io::{Image, is_film_path, write_image};
use std::path::PathBuf;

#[derive(Args, Debug, Clone)]
pub struct MergeArgs {
    /// The shards' film files.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Output image(s) (.exr, .png) and/or a merged .prism-film.
    #[arg(short, long = "output", required = true)]
    pub output: Vec<PathBuf>,
    /// Merge even if shards are missing or incomplete.
    #[arg(long)]
    pub partial: bool,
    /// PNG exposure in stops.
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pub exposure: f32,
}

pub fn run(a: MergeArgs) -> anyhow::Result<()> {
    let max = prism_core::settings::MAX_EXPOSURE;
    if !(a.exposure.is_finite() && a.exposure.abs() <= max) {
        return Err(PrismError::invalid(format!("--exposure must be between -{max} and {max} stops")).into());
    }
    for o in &a.output {
        let ext = o.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        if ext != "png" && ext != "exr" && !is_film_path(o) {
            return Err(PrismError::invalid(format!(
                "{}: unsupported output format (use .png, .exr or .prism-film)",
                o.display()
            ))
            .into());
        }
        if a.parts.iter().any(|p| p == o || prism_core::io::same_file(p, o)) {
            return Err(PrismError::invalid(format!("{}: the output would overwrite an input", o.display())).into());
        }
    }
    prism_core::io::check_outputs(&a.output, &a.parts)?;
    let mut first = read_film(&a.parts[0])?;
    let n = first.header.shard.1;
    // The shard count comes from a file: keep the shards seen in a set, never a table sized by it.
    let mut seen = std::collections::BTreeSet::from([first.header.shard.0]);
    let mut passes_done = first.header.passes_done;
    let mut spp_done = first.header.spp_done;
    let mut incomplete = vec![];
    if first.header.passes_done < first.header.passes {
        incomplete.push(format!("{}/{n}", first.header.shard.0));
    }
    for path in &a.parts[1..] {
        let f = read_film(path)?;
        let (h, h0) = (&f.header, &first.header);
        let mismatch = |what: &str| PrismError::format(path, format!("{what} differs from {}'s", a.parts[0].display()));
        if (h.width, h.height) != (h0.width, h0.height) {
            return Err(mismatch("image size").into());
        }
        if h.integrator != h0.integrator {
            return Err(mismatch("integrator").into());
        }
        if h.fingerprint != h0.fingerprint {
            return Err(mismatch("scene or settings fingerprint").into());
        }
        if h.shard.1 != n || h.axis != h0.axis {
            return Err(mismatch("shard count").into());
        }
        let k = h.shard.0;
        if !seen.insert(k) {
            return Err(PrismError::format(path, format!("shard {k}/{n} is given twice")).into());
        }
        if h.passes_done < h.passes {
            incomplete.push(format!("{k}/{n}"));
        }
        first.film.accumulate(&f.film);
        passes_done = passes_done.max(h.passes_done);
        spp_done = spp_done.saturating_add(if h.axis == ShardAxis::Passes { h.spp_done } else { 0 });
    }
    let missing_count = n as usize - seen.len();
    let mut missing: Vec<String> = (0..n).filter(|k| !seen.contains(k)).take(10).map(|k| format!("{k}/{n}")).collect();
    if missing_count > missing.len() {
        missing.push(format!("and {} more", missing_count - missing.len()));
    }
    if !missing.is_empty() && !a.partial {
        return Err(PrismError::invalid(format!(
            "shards {} are missing (merge them all, or pass --partial for the image of those given)",
            missing.join(", ")
        ))
        .into());
    }
    if !incomplete.is_empty() && !a.partial {
        return Err(PrismError::invalid(format!(
            "shards {} did not finish (resume them with `prism render --resume`, or pass --partial)",
            incomplete.join(", ")
        ))
        .into());
    }
    let film = first.film;
    let img = Image::new(film.width, film.height, film.image());
    let mut header = first.header;
    header.shard = (0, 1);
    header.passes_done = passes_done;
    header.spp_done = spp_done;
    for o in &a.output {
        if is_film_path(o) {
            // Row-sharded integrators keep per-shard state that does not merge: the merged film is an image.
            write_film(o, &header, &film, &[])?;
        } else {
            write_image(o, &img, a.exposure)?;
        }
    }
    eprintln!(
        "merged {} shard(s) of {n}: {}x{}; wrote {}",
        a.parts.len(),
        film.width,
        film.height,
        a.output.iter().map(|o| o.display().to_string()).collect::<Vec<_>>().join(", ")
    );
    Ok(())
}
