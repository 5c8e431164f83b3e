//! The report's manifest, `DIR/.prism-report`: the files a run wrote into its folder, one relative path per line.
//! The next run removes exactly those (pictures, CSVs and the page an earlier suite had, so nothing stale remains)
//! and never a file it did not write; a folder that holds files but no manifest is refused before anything is
//! rendered or removed.

use prism_core::error::{PrismError, Result};
use std::path::{Component, Path};

/// The manifest's name inside the report's folder.
pub const MANIFEST: &str = ".prism-report";

const HEADER: &str = "# Files written by `prism report` into this folder; its next run removes them.";

/// A manifest line that names a file inside the folder: relative, without `..`, `.` or a root.
fn inside(rel: &str) -> bool {
    let p = Path::new(rel);
    !rel.is_empty() && p.components().all(|c| matches!(c, Component::Normal(_)))
}

/// Prepare `out` for a run: create it if missing; otherwise remove the files its manifest lists (and the manifest),
/// or refuse a folder with files in it and no manifest.
pub fn clear(out: &Path) -> Result<()> {
    if !out.exists() {
        return std::fs::create_dir_all(out).map_err(|e| PrismError::io(out, e));
    }
    if !out.is_dir() {
        return Err(PrismError::format(out, "the report's output is not a folder"));
    }
    let manifest = out.join(MANIFEST);
    if !manifest.is_file() {
        let mut entries = std::fs::read_dir(out).map_err(|e| PrismError::io(out, e))?;
        if entries.next().is_some() {
            return Err(PrismError::format(
                out,
                format!(
                    "the folder holds files and no {MANIFEST} manifest, so `prism report` did not write it: give a new \
                     or empty folder (a report removes only the files of its own earlier run)"
                ),
            ));
        }
        return Ok(());
    }
    let text = prism_core::io::read_regular_text(&manifest, "report manifest")?;
    for rel in text.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#')) {
        let path = out.join(rel);
        // Only plain files inside the folder, whatever the manifest says.
        if inside(rel) && std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
            std::fs::remove_file(&path).map_err(|e| PrismError::io(&path, e))?;
        }
    }
    std::fs::remove_file(&manifest).map_err(|e| PrismError::io(&manifest, e))
}

/// Record the files a run wrote (relative to `out`).
pub fn write(out: &Path, files: &[String]) -> Result<()> {
    let mut text = format!("{HEADER}\n");
    for f in files.iter().filter(|f| inside(f)) {
        text += f;
        text.push('\n');
    }
    prism_core::io::write_atomic(&out.join(MANIFEST), text.as_bytes())
}

#[cfg(test)]
mod tests {
    #[test]
    fn only_plain_relative_paths_are_inside() {
        assert!(super::inside("img/a.png"));
        for bad in ["", "../x", "/etc/passwd", "img/../../x", "./x"] {
            assert!(!super::inside(bad), "{bad}");
        }
    }
}
