//! glTF binary data: the buffers (the GLB `BIN` chunk, base64 `data:` URIs, external files relative to the
//! glTF file, percent-decoded), and accessors read with every byte range and type checked first, so a
//! malformed file gives a one-line error instead of a panic or a huge allocation: offsets, strides and counts
//! are computed with checked arithmetic and must lie within their buffer view and buffer; component types and
//! dimensions must be the ones the attribute allows (POSITION, NORMAL: float VEC3; TANGENT: float VEC4;
//! TEXCOORD: float or normalised unsigned byte/short VEC2; indices: unsigned byte/short/int SCALAR); sparse
//! accessors are applied with their indices checked.

use base64::Engine as _;
use gltf::accessor::{DataType, Dimensions};
use prism_core::error::{PrismError, Result};
use std::path::{Path, PathBuf};

/// The bytes of every buffer of a document.
pub struct Buffers {
    pub data: Vec<Vec<u8>>,
}

/// `%XX` escapes of a relative URI decoded.
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%'
            && i + 2 < b.len()
            && let Ok(v) = u8::from_str_radix(&s[i + 1..i + 3], 16)
        {
            out.push(v);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The bytes a URI names: a base64 `data:` URI, or a file relative to `base`.
/// With `base` `None` (a glTF given as bytes), files resolve to nothing.
pub fn uri_bytes(uri: &str, base: Option<&Path>, what: &str, file: &Path) -> Result<Vec<u8>> {
    let err = |m: String| PrismError::format(file, format!("{what}: {m}"));
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest.split_once(";base64,").ok_or_else(|| err("a data URI that is not base64".into()))?;
        return base64::engine::general_purpose::STANDARD
            .decode(payload.trim())
            .map_err(|e| err(format!("bad base64 data URI: {e}")));
    }
    if uri.contains("://") {
        return Err(err(format!("URI scheme not supported (only relative files and data URIs): {uri}")));
    }
    let Some(base) = base else {
        return Err(err(format!("the external file {uri} is not read (glTF given as bytes)")));
    };
    let path: PathBuf = base.join(percent_decode(uri));
    // A regular file only: a device or a pipe named by the URI would never end.
    prism_core::io::read_regular(&path, "file").map_err(|e| err(format!("cannot read {}: {e}", path.display())))
}

/// The files a glTF document reads beside itself: its buffers' and images' URIs that are not `data:` URIs, resolved
/// against `base` (the scene's inputs, which no output may overwrite).
pub fn external_files(doc: &gltf::Document, base: &Path) -> Vec<PathBuf> {
    let buffers = doc.buffers().filter_map(|b| match b.source() {
        gltf::buffer::Source::Uri(uri) => Some(uri),
        gltf::buffer::Source::Bin => None,
    });
    let images = doc.images().filter_map(|i| match i.source() {
        gltf::image::Source::Uri { uri, .. } => Some(uri),
        gltf::image::Source::View { .. } => None,
    });
    buffers
        .chain(images)
        .filter(|uri| !uri.starts_with("data:") && !uri.contains("://"))
        .map(|uri| base.join(percent_decode(uri)))
        .collect()
}

impl Buffers {
    /// Load every buffer; each must hold at least its declared `byteLength`.
    pub fn load(doc: &gltf::Document, blob: Option<Vec<u8>>, base: Option<&Path>, file: &Path) -> Result<Self> {
        let mut blob = blob;
        let mut data = Vec::new();
        for b in doc.buffers() {
            let what = format!("buffer {}", b.index());
            let bytes = match b.source() {
                gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                    PrismError::format(file, format!("{what} refers to the GLB binary chunk, which is missing"))
                })?,
                gltf::buffer::Source::Uri(uri) => uri_bytes(uri, base, &what, file)?,
            };
            if bytes.len() < b.length() {
                return Err(PrismError::format(
                    file,
                    format!("{what} declares {} bytes but holds only {} (truncated?)", b.length(), bytes.len()),
                ));
            }
            data.push(bytes);
        }
        Ok(Buffers { data })
    }

    /// The bytes of a buffer view, checked against its buffer.
    pub fn view(&self, v: &gltf::buffer::View, what: &str, file: &Path) -> Result<&[u8]> {
        let buf = &self.data[v.buffer().index()];
        let end = v.offset().checked_add(v.length());
        match end {
            Some(end) if end <= buf.len() => Ok(&buf[v.offset()..end]),
            _ => Err(PrismError::format(
                file,
                format!(
                    "{what}: buffer view {} (offset {}, length {}) lies outside buffer {} ({} bytes)",
                    v.index(),
                    v.offset(),
                    v.length(),
                    v.buffer().index(),
                    buf.len()
                ),
            )),
        }
    }
}

fn comp_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

fn comps(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

/// One component as f64 (normalised integers mapped to [0, 1]).
fn read_comp(b: &[u8], t: DataType, normalized: bool) -> f64 {
    let v = match t {
        DataType::F32 => return f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
        DataType::U8 => (b[0] as f64, 255.0),
        DataType::I8 => (b[0] as i8 as f64, 127.0),
        DataType::U16 => (u16::from_le_bytes([b[0], b[1]]) as f64, 65535.0),
        DataType::I16 => (i16::from_le_bytes([b[0], b[1]]) as f64, 32767.0),
        DataType::U32 => (u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64, 4294967295.0),
    };
    if normalized { (v.0 / v.1).max(-1.0) } else { v.0 }
}

/// Read an accessor as `count` rows of `n` components, after checking its type and byte ranges. `allowed` lists
/// the (component type, normalised) pairs the caller accepts.
pub fn read_accessor(
    a: &gltf::Accessor,
    buffers: &Buffers,
    n: usize,
    allowed: &[(DataType, bool)],
    what: &str,
    file: &Path,
) -> Result<Vec<f64>> {
    let err = |m: String| PrismError::format(file, format!("{what}: accessor {}: {m}", a.index()));
    if comps(a.dimensions()) != n {
        return Err(err(format!("has type {:?}, expected {n} components", a.dimensions())));
    }
    let (t, norm) = (a.data_type(), a.normalized());
    if !allowed.contains(&(t, norm)) {
        return Err(err(format!(
            "component type {t:?}{} is not allowed here (expected {})",
            if norm { " normalised" } else { "" },
            allowed
                .iter()
                .map(|(t, n)| format!("{t:?}{}", if *n { " normalised" } else { "" }))
                .collect::<Vec<_>>()
                .join(" or ")
        )));
    }
    let count = a.count();
    let elem = comp_size(t) * n;
    // The data must be there before anything is allocated from the count.
    let mut out = match a.view() {
        Some(v) => {
            let bytes = buffers.view(&v, what, file)?;
            let stride = v.stride().unwrap_or(elem);
            if stride < elem {
                return Err(err(format!("byte stride {stride} is smaller than an element ({elem} bytes)")));
            }
            let needed = if count == 0 {
                Some(0)
            } else {
                stride.checked_mul(count - 1).and_then(|x| x.checked_add(elem)).and_then(|x| x.checked_add(a.offset()))
            };
            match needed {
                Some(end) if end <= bytes.len() => {}
                _ => {
                    return Err(err(format!(
                        "{count} elements of {elem} bytes (stride {stride}, offset {}) overrun buffer view {} of {} bytes",
                        a.offset(),
                        v.index(),
                        bytes.len()
                    )));
                }
            }
            let mut out = Vec::with_capacity(count * n);
            let cs = comp_size(t);
            for i in 0..count {
                let at = a.offset() + i * stride;
                for k in 0..n {
                    out.push(read_comp(&bytes[at + k * cs..], t, norm));
                }
            }
            out
        }
        None if a.sparse().is_some() => {
            // All zeros but the sparse values; the count is bounded by what the sparse data must cover.
            if count > 1 << 26 {
                return Err(err(format!("{count} elements without a buffer view is too many")));
            }
            vec![0.0; count * n]
        }
        None => return Err(err("has neither a buffer view nor sparse values".into())),
    };
    if let Some(s) = a.sparse() {
        let sc = s.count();
        let iv = buffers.view(&s.indices().view(), what, file)?;
        let vv = buffers.view(&s.values().view(), what, file)?;
        let isz = s.indices().index_type().size();
        let (ie, ve) = (
            sc.checked_mul(isz).and_then(|x| x.checked_add(s.indices().offset())),
            sc.checked_mul(elem).and_then(|x| x.checked_add(s.values().offset())),
        );
        if !matches!(ie, Some(e) if e <= iv.len()) || !matches!(ve, Some(e) if e <= vv.len()) {
            return Err(err(format!("sparse data of {sc} elements overruns its buffer views")));
        }
        for j in 0..sc {
            let b = &iv[s.indices().offset() + j * isz..];
            let idx = match isz {
                1 => b[0] as usize,
                2 => u16::from_le_bytes([b[0], b[1]]) as usize,
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
            };
            if idx >= count {
                return Err(err(format!("sparse index {idx} is beyond the {count} elements")));
            }
            for k in 0..n {
                out[idx * n + k] = read_comp(&vv[s.values().offset() + j * elem + k * comp_size(t)..], t, norm);
            }
        }
    }
    Ok(out)
}
