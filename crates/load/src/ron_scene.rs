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
        if name.contains('(') {
            return Err(err(format!(
                "an integrator with parameters is written without quotes: `integrator: {}`",
                name.trim()
            )));
        }
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

/// The 1-based line and column of field `field` of the top-level struct field `block` in RON scene text
/// (`render: (spp: 0)`: block `render`, field `spp`), skipping strings and comments; `None` when the text does not
/// give it.
pub fn field_position(text: &str, block: &str, field: &str) -> Option<(usize, usize)> {
    let b = text.as_bytes();
    let ident_at = |i: usize, name: &str| {
        b[i..].starts_with(name.as_bytes())
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'))
            && b.get(i + name.len()).is_none_or(|c| !(c.is_ascii_alphanumeric() || *c == b'_'))
    };
    let colon_after = |mut i: usize| {
        while i < b.len() && b[i].is_ascii_whitespace() {
            i += 1;
        }
        b.get(i) == Some(&b':')
    };
    // Depth of parentheses, brackets and braces; the scene's own fields are at depth 1.
    let (mut depth, mut i, mut in_block) = (0usize, 0usize, None::<usize>);
    while i < b.len() {
        match b[i] {
            b'"' => {
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
            }
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i + 1 < b.len() && !(b[i] == b'*' && b[i + 1] == b'/') {
                    i += 1;
                }
                i += 1;
            }
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => {
                depth = depth.saturating_sub(1);
                if in_block.is_some_and(|d| depth < d) {
                    in_block = None;
                }
            }
            _ if depth == 1 && in_block.is_none() && ident_at(i, block) && colon_after(i + block.len()) => {
                in_block = Some(2);
                i += block.len();
                continue;
            }
            _ if in_block == Some(depth) && ident_at(i, field) && colon_after(i + field.len()) => {
                return Some(line_col(text, i));
            }
            _ => {}
        }
        i += 1;
    }
    None
}
