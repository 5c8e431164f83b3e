//! Image textures: a decoded image (PNG, JPEG, Radiance HDR or OpenEXR) as linear f32 RGB texels, and its lookup
//! with the conventions of Mitsuba 3's `bitmap` texture (`../shared/refs/textured.md`):
//!
//! - texel (row r, column c) of a W x H image, row 0 being the image's first (top) row, has its centre at
//!   `(u, v) = ((c + 0.5) / W, (r + 0.5) / H)`: v grows downwards in the picture and nothing is flipped;
//! - bilinear: `x = u W - 0.5`, `y = v H - 0.5`, weights `fx = x - floor(x)`, `fy = y - floor(y)` on the four
//!   texels around, each index wrapped by the wrap mode (`repeat`: modulo the size; `clamp`: to the edge texel;
//!   `mirror`: reflected at every edge, period 2W);
//! - 8-bit and 16-bit colour images are decoded from sRGB to linear texel by texel BEFORE interpolation; data
//!   images (`raw`: normal, roughness or height maps) keep `byte / 255`; HDR and EXR texels are linear already.
//!
//! A uv transform `uv' = uv * scale + offset` is applied before the lookup. Images are decoded once per (file,
//! raw) and shared between the textures and materials that use them.
//!
//! Storage: texels are kept as the file gave them. 8-bit images stay 8-bit (3 bytes a texel, 1 for grey ones),
//! decoded through a table of the 256 values at each lookup (the same values the decoded texels had, so lookups
//! are unchanged bit for bit); float and 16-bit images are linear f32 RGB.

use crate::error::{PrismError, Result};
use crate::io::srgb_to_linear;
use crate::math::floor_f32;
use glam::{Vec2, Vec3};
use serde::Deserialize;
use std::path::Path;

/// Largest width or height accepted (a guard against absurd headers).
pub const MAX_TEXTURE_SIZE: u32 = 16384;

/// How texel indices outside the image are brought back into it.
#[derive(Deserialize, Debug, Clone, Copy, Default, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Wrap {
    /// Tile the image (index modulo the size).
    #[default]
    Repeat,
    /// Use the edge texel.
    Clamp,
    /// Tile with every other copy mirrored (period twice the size).
    Mirror,
}

impl Wrap {
    /// Indices `i` and `i + 1` wrapped into `[0, n)`: the two columns (or rows) of a bilinear lookup. Where both
    /// lie inside the image (nearly every lookup of a uv in [0, 1)) every mode leaves them as they are, which
    /// spares the two 64-bit divisions of `rem_euclid` (four per lookup; together with library `floorf` calls,
    /// which `math::floor_f32` avoids, about 40% of a lookup's time).
    #[inline]
    pub fn index_pair(self, i: i64, n: u32) -> (usize, usize) {
        if i >= 0 && i + 1 < n as i64 { (i as usize, i as usize + 1) } else { (self.index(i, n), self.index(i + 1, n)) }
    }

    /// Index `i` wrapped into `[0, n)`.
    #[inline]
    pub fn index(self, i: i64, n: u32) -> usize {
        let n = n as i64;
        (match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m < n { m } else { 2 * n - 1 - m }
            }
        }) as usize
    }
}

/// The decoded value of each byte: `byte / 255` for data, sRGB-decoded for colour.
type ByteTable = [f32; 256];

/// `byte / 255`.
static RAW_TABLE: std::sync::LazyLock<ByteTable> =
    std::sync::LazyLock::new(|| std::array::from_fn(|b| b as f32 / 255.0));
/// `srgb_to_linear(byte / 255)`.
static SRGB_TABLE: std::sync::LazyLock<ByteTable> =
    std::sync::LazyLock::new(|| std::array::from_fn(|b| srgb_to_linear(b as f32 / 255.0)));
/// `(byte / 255)^2`: a glTF roughness map as GGX alpha.
static SQUARED_TABLE: std::sync::LazyLock<ByteTable> = std::sync::LazyLock::new(|| {
    std::array::from_fn(|b| {
        let c = b as f32 / 255.0;
        c * c
    })
});

/// How an image's stored values (8 or 16 bits, as a fraction `c` in [0, 1]) decode to linear values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ByteDecoding {
    /// `c` (data maps: normal, roughness, height, alpha).
    Raw,
    /// sRGB-decoded `c` (colour).
    Srgb,
    /// `c^2` (a roughness map used as GGX alpha).
    Squared,
    /// `c^gamma` (pbrt's `"encoding" "gamma g"`), `gamma` finite and positive.
    Gamma(f32),
}

impl ByteDecoding {
    /// The decoded value of the stored fraction `c`.
    pub fn decode(self, c: f32) -> f32 {
        match self {
            ByteDecoding::Raw => c,
            ByteDecoding::Srgb => srgb_to_linear(c),
            ByteDecoding::Squared => c * c,
            ByteDecoding::Gamma(g) => c.powf(g),
        }
    }

    fn table(self) -> &'static ByteTable {
        match self {
            ByteDecoding::Raw => &RAW_TABLE,
            ByteDecoding::Srgb => &SRGB_TABLE,
            ByteDecoding::Squared => &SQUARED_TABLE,
            ByteDecoding::Gamma(g) => {
                // One table per exponent, kept for the process's life.
                type Tables = std::collections::HashMap<u32, &'static ByteTable>;
                static TABLES: std::sync::OnceLock<std::sync::Mutex<Tables>> = std::sync::OnceLock::new();
                let mut t = TABLES.get_or_init(Default::default).lock().unwrap_or_else(|e| e.into_inner());
                t.entry(g.to_bits())
                    .or_insert_with(|| Box::leak(Box::new(std::array::from_fn(|b| (b as f32 / 255.0).powf(g)))))
            }
        }
    }
}

/// Texel storage (see the module doc).
#[derive(Clone)]
enum Texels {
    /// Linear RGB.
    Rgb32(Vec<Vec3>),
    /// 8-bit RGB decoded through a table.
    Rgb8 { bytes: Vec<[u8; 3]>, table: &'static ByteTable },
    /// 8-bit grey decoded through a table.
    Gray8 { bytes: Vec<u8>, table: &'static ByteTable },
}

impl std::fmt::Debug for Texels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Texels::Rgb32(t) => write!(f, "Rgb32({} texels)", t.len()),
            Texels::Rgb8 { bytes, .. } => write!(f, "Rgb8({} texels)", bytes.len()),
            Texels::Gray8 { bytes, .. } => write!(f, "Gray8({} texels)", bytes.len()),
        }
    }
}

/// A decoded image: RGB texels (8-bit as stored, or linear f32), row 0 at the top.
#[derive(Clone, Debug)]
pub struct TexImage {
    /// Width in texels (1 to [`MAX_TEXTURE_SIZE`] for loaded files).
    pub width: u32,
    /// Height in texels (1 to [`MAX_TEXTURE_SIZE`] for loaded files).
    pub height: u32,
    /// `width * height` texels, row-major from the top row, all finite once decoded.
    texels: Texels,
    /// The file had one (grey) channel: every texel has r = g = b.
    pub gray: bool,
}

impl PartialEq for TexImage {
    /// Equal sizes and equal decoded texels.
    fn eq(&self, other: &Self) -> bool {
        self.width == other.width
            && self.height == other.height
            && self.gray == other.gray
            && self.iter().zip(other.iter()).all(|(a, b)| a == b)
    }
}

impl TexImage {
    /// An image from texels given row by row from the top (for procedurally made textures and tests).
    pub fn from_texels(width: u32, height: u32, texels: Vec<Vec3>) -> Result<Self> {
        if width == 0 || height == 0 || texels.len() != width as usize * height as usize {
            return Err(PrismError::invalid(format!(
                "texture image {width}x{height} needs {} texels, got {}",
                width as usize * height as usize,
                texels.len()
            )));
        }
        Ok(TexImage { width, height, texels: Texels::Rgb32(texels), gray: false })
    }

    /// Number of texels (`width * height`).
    pub fn len(&self) -> usize {
        match &self.texels {
            Texels::Rgb32(t) => t.len(),
            Texels::Rgb8 { bytes, .. } => bytes.len(),
            Texels::Gray8 { bytes, .. } => bytes.len(),
        }
    }

    /// True for an image without texels (never for a loaded one).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Texel `i` (row-major from the top row), decoded to linear RGB.
    #[inline]
    pub fn texel_at(&self, i: usize) -> Vec3 {
        match &self.texels {
            Texels::Rgb32(t) => t[i],
            Texels::Rgb8 { bytes, table } => {
                let b = bytes[i];
                Vec3::new(table[b[0] as usize], table[b[1] as usize], table[b[2] as usize])
            }
            Texels::Gray8 { bytes, table } => Vec3::splat(table[bytes[i] as usize]),
        }
    }

    /// Every texel, decoded, row-major from the top row.
    pub fn iter(&self) -> impl Iterator<Item = Vec3> + '_ {
        (0..self.len()).map(|i| self.texel_at(i))
    }

    /// Bytes the texels take in memory.
    pub fn texel_bytes(&self) -> usize {
        match &self.texels {
            Texels::Rgb32(t) => t.len() * std::mem::size_of::<Vec3>(),
            Texels::Rgb8 { bytes, .. } => bytes.len() * 3,
            Texels::Gray8 { bytes, .. } => bytes.len(),
        }
    }

    /// Read an image file. `raw`: keep 8/16-bit values as stored (data maps); otherwise decode them from sRGB.
    pub fn load(path: &Path, raw: bool) -> Result<Self> {
        Self::load_decoded(path, if raw { ByteDecoding::Raw } else { ByteDecoding::Srgb })
    }

    /// [`TexImage::load`] with 8/16-bit values decoded by `decoding` (float images are linear as they are).
    pub fn load_decoded(path: &Path, decoding: ByteDecoding) -> Result<Self> {
        crate::io::open_regular(path, "texture file")?;
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        let img = if ext == "exr" {
            let im = crate::io::read_exr(path)?;
            TexImage { width: im.width, height: im.height, texels: Texels::Rgb32(im.pixels), gray: false }
        } else {
            Self::decode(path, decoding)?
        };
        if img.width == 0 || img.height == 0 || img.len() != img.width as usize * img.height as usize {
            return Err(PrismError::format(path, format!("texture has no pixels ({}x{})", img.width, img.height)));
        }
        if img.width > MAX_TEXTURE_SIZE || img.height > MAX_TEXTURE_SIZE {
            return Err(PrismError::format(
                path,
                format!("texture is {}x{}, larger than {MAX_TEXTURE_SIZE} on a side", img.width, img.height),
            ));
        }
        if let Some(i) = img.iter().position(|t| !t.is_finite()) {
            return Err(PrismError::format(
                path,
                format!("texel (row {}, column {}) is NaN or infinite", i as u32 / img.width, i as u32 % img.width),
            ));
        }
        Ok(img)
    }

    /// PNG, JPEG or Radiance HDR through the image crate.
    fn decode(path: &Path, decoding: ByteDecoding) -> Result<Self> {
        let reader = image::ImageReader::open(path)
            .map_err(|e| PrismError::io(path, e))?
            .with_guessed_format()
            .map_err(|e| PrismError::io(path, e))?;
        Ok(Self::from_dynamic_decoded(&Self::decode_reader(reader, path)?, decoding))
    }

    /// Decode an image held in memory (PNG, JPEG or Radiance HDR; a glTF buffer view or data URI). `what` names
    /// the source in errors. Sizes above [`MAX_TEXTURE_SIZE`] are refused before any pixel is allocated.
    pub fn decode_bytes(bytes: &[u8], what: &Path) -> Result<image::DynamicImage> {
        let reader = image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| PrismError::io(what, e))?;
        Self::decode_reader(reader, what)
    }

    fn decode_reader<R: std::io::BufRead + std::io::Seek>(
        mut reader: image::ImageReader<R>,
        what: &Path,
    ) -> Result<image::DynamicImage> {
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_TEXTURE_SIZE);
        limits.max_image_height = Some(MAX_TEXTURE_SIZE);
        reader.limits(limits);
        let img = crate::io::decode_checked(reader)
            .map_err(|e| PrismError::format(what, format!("cannot decode texture image: {e}")))?;
        if img.width() == 0 || img.height() == 0 {
            return Err(PrismError::format(what, "texture has no pixels"));
        }
        Ok(img)
    }

    /// The texels of a decoded image: 8-bit images kept as bytes (decoded from sRGB at lookup unless `raw`), 16-bit
    /// ones decoded to f32 (from sRGB unless `raw`), float images as they are.
    pub fn from_dynamic(dynimg: &image::DynamicImage, raw: bool) -> Self {
        Self::from_dynamic_decoded(dynimg, if raw { ByteDecoding::Raw } else { ByteDecoding::Srgb })
    }

    /// [`TexImage::from_dynamic`] with 8/16-bit values decoded by `decoding`.
    pub fn from_dynamic_decoded(dynimg: &image::DynamicImage, decoding: ByteDecoding) -> Self {
        use image::ColorType as C;
        let color = dynimg.color();
        let gray = matches!(color, C::L8 | C::La8 | C::L16 | C::La16);
        let float = matches!(color, C::Rgb32F | C::Rgba32F);
        let (w, h) = (dynimg.width(), dynimg.height());
        let texels = if float {
            Texels::Rgb32(dynimg.to_rgb32f().pixels().map(|p| Vec3::new(p[0], p[1], p[2])).collect())
        } else if matches!(color, C::L16 | C::La16 | C::Rgb16 | C::Rgba16) {
            let dec = |v: u16| decoding.decode(v as f32 / 65535.0);
            Texels::Rgb32(dynimg.to_rgb16().pixels().map(|p| Vec3::new(dec(p[0]), dec(p[1]), dec(p[2]))).collect())
        } else {
            let table = decoding.table();
            if gray {
                Texels::Gray8 { bytes: dynimg.to_luma8().into_raw(), table }
            } else {
                Texels::Rgb8 { bytes: dynimg.to_rgb8().pixels().map(|p| p.0).collect(), table }
            }
        };
        TexImage { width: w, height: h, texels, gray }
    }

    /// One channel (0 red, 1 green, 2 blue) of a decoded image as a grey image, decoded by `decoding` (8-bit
    /// images stay 8-bit; the others' linear values are decoded the same way).
    pub fn channel_from_dynamic(dynimg: &image::DynamicImage, channel: usize, decoding: ByteDecoding) -> Self {
        use image::ColorType as C;
        let (w, h) = (dynimg.width(), dynimg.height());
        let texels = match dynimg.color() {
            C::L8 | C::La8 => Texels::Gray8 { bytes: dynimg.to_luma8().into_raw(), table: decoding.table() },
            C::Rgb8 | C::Rgba8 => Texels::Gray8 {
                bytes: dynimg.to_rgb8().pixels().map(|p| p[channel.min(2)]).collect(),
                table: decoding.table(),
            },
            _ => Texels::Rgb32(
                dynimg.to_rgb32f().pixels().map(|p| Vec3::splat(decoding.decode(p[channel.min(2)]))).collect(),
            ),
        };
        TexImage { width: w, height: h, texels, gray: true }
    }

    /// The alpha channel of a decoded image as a grey image (linear: alpha is never sRGB-encoded), or `None` when
    /// the image has no alpha channel.
    pub fn alpha_from_dynamic(dynimg: &image::DynamicImage) -> Option<Self> {
        if !dynimg.color().has_alpha() {
            return None;
        }
        let (w, h) = (dynimg.width(), dynimg.height());
        let texels = if matches!(dynimg.color(), image::ColorType::La8 | image::ColorType::Rgba8) {
            Texels::Gray8 { bytes: dynimg.to_rgba8().pixels().map(|p| p[3]).collect(), table: &RAW_TABLE }
        } else {
            Texels::Rgb32(dynimg.to_rgba32f().pixels().map(|p| Vec3::splat(p[3])).collect())
        };
        Some(TexImage { width: w, height: h, texels, gray: true })
    }

    /// Bilinear lookup at `uv` (texel centres at half-integers, v downwards), indices wrapped by `wrap`.
    #[inline]
    pub fn bilinear(&self, uv: Vec2, wrap: Wrap) -> Vec3 {
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        if !(x.is_finite() && y.is_finite()) {
            return Vec3::ZERO;
        }
        let (x0, y0) = (floor_f32(x), floor_f32(y));
        let (fx, fy) = (x - x0, y - y0);
        // Far-away uvs lose their fraction in f32; clamp the integer part so the i64 conversion stays exact.
        let (x0, y0) = (x0.clamp(-1e9, 1e9) as i64, y0.clamp(-1e9, 1e9) as i64);
        let (c0, c1) = wrap.index_pair(x0, self.width);
        let (r0, r1) = wrap.index_pair(y0, self.height);
        let w = self.width as usize;
        let idx = [r0 * w + c0, r0 * w + c1, r1 * w + c0, r1 * w + c1];
        // One match for the four texels.
        let [t00, t01, t10, t11] = match &self.texels {
            Texels::Rgb32(t) => idx.map(|i| t[i]),
            Texels::Rgb8 { bytes, table } => idx.map(|i| {
                let b = bytes[i];
                Vec3::new(table[b[0] as usize], table[b[1] as usize], table[b[2] as usize])
            }),
            Texels::Gray8 { bytes, table } => idx.map(|i| Vec3::splat(table[bytes[i] as usize])),
        };
        (1.0 - fx) * (1.0 - fy) * t00 + fx * (1.0 - fy) * t01 + (1.0 - fx) * fy * t10 + fx * fy * t11
    }
}

/// An image used as a texture: the shared image, its wrap mode and uv transform.
#[derive(Clone, Debug)]
pub struct ImageMap {
    /// The decoded image, shared between the textures that use the file.
    pub image: std::sync::Arc<TexImage>,
    /// How lookups outside the unit square wrap.
    pub wrap: Wrap,
    /// `uv' = R (uv * uv_scale) + uv_offset`, `R` the rotation of `uv_rotation` (glTF's `KHR_texture_transform`
    /// order: scale, rotate, translate).
    pub uv_scale: Vec2,
    /// Added to the scaled and rotated uv (see `uv_scale`).
    pub uv_offset: Vec2,
    /// `(cos a, sin a)` of the uv rotation by `a`: `R (x, y) = (cos a x + sin a y, -sin a x + cos a y)`, the
    /// specification's GLSL `mat3(cos, sin, 0, -sin, cos, 0, 0, 0, 1)` read row by row: the direction glTF viewers
    /// use and Khronos' TextureTransformTest checks (its arrow points at the green marker; the column-major
    /// reading points it at the red "opposite direction" one). `(1, 0)` is none.
    pub uv_rotation: Vec2,
}

impl ImageMap {
    /// No rotation, for [`ImageMap::uv_rotation`].
    pub const NO_ROTATION: Vec2 = Vec2::new(1.0, 0.0);

    /// The map's uv for surface coordinates `uv`.
    #[inline]
    pub fn transform_uv(&self, uv: Vec2) -> Vec2 {
        let s = uv * self.uv_scale;
        let r = if self.uv_rotation == Self::NO_ROTATION {
            s
        } else {
            let (c, sn) = (self.uv_rotation.x, self.uv_rotation.y);
            Vec2::new(c * s.x + sn * s.y, -sn * s.x + c * s.y)
        };
        r + self.uv_offset
    }
}

impl ImageMap {
    /// The bilinearly filtered texel value at surface coordinates `uv`, after the uv transform (0 for
    /// non-finite coordinates).
    #[inline]
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        self.image.bilinear(self.transform_uv(uv), self.wrap)
    }
}
