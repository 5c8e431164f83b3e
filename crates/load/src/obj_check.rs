//! Line-level checks of OBJ and MTL text, for errors that name `file:line`: tobj reports what went wrong but not
//! where, so when it fails (or returns values Prism rejects) the text is scanned for the first offending line.
//!
//! OBJ: `v`, `vn` and `vt` need finite numbers (3, 3 and at least 1); face indices are 1-based (negative ones
//! count back from the last vertex read) and must name vertices defined before the face. MTL: `Kd`, `Ks`, `Ke`,
//! `Tf` are finite non-negative colours, `Ns` a finite non-negative exponent, `Ni` a finite positive index.

/// The first line of OBJ text that Prism rejects: (1-based line, message).
pub fn diagnose_obj(text: &str) -> Option<(usize, String)> {
    let mut counts = [0i64; 3]; // v, vt, vn
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let problem = match words.next() {
            Some("v") => numbers(words, 3, "vertex position `v`").map(|()| counts[0] += 1).err(),
            Some("vt") => numbers(words, 2, "texture coordinate `vt`").map(|()| counts[1] += 1).err(),
            Some("vn") => numbers(words, 3, "normal `vn`").map(|()| counts[2] += 1).err(),
            Some("f") => face(words, &counts).err(),
            _ => None,
        };
        if let Some(p) = problem {
            return Some((i + 1, p));
        }
    }
    None
}

/// At least `need` numbers, the first `need` (at most 3) finite.
fn numbers<'a>(words: impl Iterator<Item = &'a str>, need: usize, what: &str) -> Result<(), String> {
    let values: Vec<&str> = words.take(3).collect();
    if values.len() < need {
        return Err(format!("{what} needs {need} numbers, found {}", values.len()));
    }
    for w in &values {
        match w.parse::<f32>() {
            Ok(v) if v.is_finite() => {}
            Ok(_) => return Err(format!("{what} has a non-finite value `{}`", printable(w))),
            Err(_) => return Err(format!("{what} has `{}`, which is not a number", printable(w))),
        }
    }
    Ok(())
}

/// Every `v/vt/vn` index of a face refers to an element defined above the face.
fn face<'a>(words: impl Iterator<Item = &'a str>, counts: &[i64; 3]) -> Result<(), String> {
    let mut corners = 0;
    for w in words {
        corners += 1;
        for (k, part) in w.split('/').enumerate().take(3) {
            if part.is_empty() {
                if k == 0 {
                    return Err(format!("face corner `{}` has no vertex index", printable(w)));
                }
                continue;
            }
            let what = ["vertex", "texture coordinate", "normal"][k];
            let plural = ["vertices", "texture coordinates", "normals"][k];
            let idx: i64 = part.parse().map_err(|_| format!("face index `{}` is not an integer", printable(part)))?;
            let n = counts[k];
            let ok = if idx > 0 { idx <= n } else { idx < 0 && -idx <= n };
            if !ok {
                return Err(format!("face refers to {what} {idx}, but {n} {plural} are defined above it"));
            }
        }
    }
    if corners < 3 {
        return Err(format!("a face needs at least 3 corners, found {corners}"));
    }
    Ok(())
}

/// The first line of MTL text that Prism rejects before handing it to tobj: colours `Ka`, `Kd`, `Ks`, `Ke` need
/// three numbers (tobj 4.0.5 panics on fewer).
pub fn diagnose_mtl(text: &str) -> Option<(usize, String)> {
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next() {
            let values: Vec<&str> = words.take(3).collect();
            if values.len() < 3 || values.iter().any(|w| w.parse::<f32>().is_err()) {
                return Some((
                    i + 1,
                    format!("colour `{key}` needs three numbers, found `{}`", printable(&values.join(" "))),
                ));
            }
        }
    }
    None
}

/// The line of `key` in material `name` of MTL text (its last occurrence, the one that counts), or of
/// `newmtl name`, or 1.
pub fn mtl_line(text: &str, name: &str, key: &str) -> usize {
    let mut in_material = false;
    let (mut material_line, mut key_line) = (None, None);
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("newmtl") => {
                in_material = words.collect::<Vec<_>>().join(" ") == name;
                if in_material {
                    material_line = Some(i + 1);
                }
            }
            Some(k) if in_material && k == key => key_line = Some(i + 1),
            _ => {}
        }
    }
    key_line.or(material_line).unwrap_or(1)
}

/// `s` with control characters escaped (file content quoted in messages stays on one printable line).
pub fn printable(s: &str) -> String {
    prism_core::error::printable(s)
}
