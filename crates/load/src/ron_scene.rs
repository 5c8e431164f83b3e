//! Parse RON scene text into the schema of `schema.rs`, turning RON's errors into `file:line:column: message`, and
//! extract the `integrator: name(params)` plugin configuration with the position of its parameters.

use super::schema::SceneDesc;
use prism_core::error::{PrismError, Result, SourcePos};
use prism_core::settings::PluginConfig;
use ron::extensions::Extensions;
use ron::value::RawValue;
use std::path::Path;

/// Parse scene text. `file` only names the source in errors.
pub fn parse_scene<'a>(text: &'a str, file: &Path) -> Result<SceneDesc<'a>> {
    let opts = ron::Options::default()
        .with_default_extension(Extensions::IMPLICIT_SOME)
        .with_recursion_limit(super::RON_RECURSION_LIMIT);
    opts.from_str::<SceneDesc>(text).map_err(|e| PrismError::Parse {
        pos: SourcePos { file: file.to_path_buf(), line: e.span.start.line, col: e.span.start.col },
        message: prism_core::ron_error::describe(&e.code),
    })
}

/// 1-based line and column of byte `offset` in `text`.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rfind('\n').map_or(before.chars().count(), |i| before[i + 1..].chars().count()) + 1;
    (line, col)
}

/// `name`, `"name"` or `name(params...)` to a plugin config; `text` is the whole file (the raw value borrows it).
pub fn plugin_config(raw: &RawValue, text: &str, file: &Path) -> Result<PluginConfig> {
    let s = raw.get_ron();
    let base = (s.as_ptr() as usize).wrapping_sub(text.as_ptr() as usize);
    let base = if base <= text.len() { base } else { 0 };
    let lead = s.len() - s.trim_start().len();
    let s = s.trim();
    let err = |msg: String| {
        let (line, col) = line_col(text, base + lead);
        PrismError::Parse { pos: SourcePos { file: file.to_path_buf(), line, col }, message: msg }
    };
    if s.starts_with('"') {
        let name: String = ron::from_str(s).map_err(|e| err(format!("integrator name: {}", e.code)))?;
        return Ok(PluginConfig::named(name));
    }
    let ident_len = s.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(s.len());
    if ident_len == 0 {
        return Err(err(format!("expected an integrator name like `phong` or `phong(max_depth: 4)`, found `{s}`")));
    }
    let name = &s[..ident_len];
    let rest = &s[ident_len..];
    let rest_trim = rest.trim_start();
    if rest_trim.is_empty() {
        return Ok(PluginConfig::named(name));
    }
    if !rest_trim.starts_with('(') {
        return Err(err(format!("expected `(` after integrator name `{name}`")));
    }
    let offset = base + lead + ident_len + (rest.len() - rest_trim.len());
    let (line, col) = line_col(text, offset);
    Ok(PluginConfig {
        name: name.to_string(),
        params: Some(rest_trim.to_string()),
        origin: Some(SourcePos { file: file.to_path_buf(), line, col }),
    })
}
