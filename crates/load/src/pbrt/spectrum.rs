//! Spectra of pbrt scenes turned into Prism's linear sRGB: sampled spectra and blackbodies are integrated against
//! the CIE 1931 colour-matching functions (the multi-lobe Gaussian fit of Wyman, Sloan & Shirley 2013, within
//! about 1% of the tabulated curves) over 360-830 nm at 1 nm, then XYZ -> linear sRGB (pbrt-v3's matrix).
//!
//! - pbrt-v3 `blackbody [T scale]`: Planck's law normalised to 1 at its peak (Wien's law), times `scale`, through
//!   XYZ exactly as pbrt-v3's `RGBSpectrum::FromSampled` (1 nm CIE samples, normalised by the CIE Y integral
//!   106.856895); `glass.pbrt`'s `rgb I [139.81 118.64 105.39]` is pbrt's own conversion of the caustic scene's
//!   `blackbody I [5500 125]`, and this gives it within 0.3% (tested).
//! - pbrt-v4 `blackbody T`: the same shape normalised to luminance Y = 1 (pbrt-v4 divides light spectra by their
//!   photometric value, so a blackbody light is as bright as `rgb L [1 1 1]`).
//! - `spectrum [l0 v0 l1 v1 ...]`: piecewise linear, 0 outside its range.
//! - named spectra: pbrt-v4's `metal-X-eta`/`metal-X-k` for the metals Prism knows (Au, Ag, Al, Cu: their RGB
//!   index), `glass-*` as their index at 550 nm; other names are an error naming them.

fn lobe(x: f64, mu: f64, s1: f64, s2: f64) -> f64 {
    let t = (x - mu) / if x < mu { s1 } else { s2 };
    (-0.5 * t * t).exp()
}

/// CIE 1931 x-bar, y-bar, z-bar at wavelength `l` (nm).
pub fn cie_xyz(l: f64) -> [f64; 3] {
    [
        1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) - 0.065 * lobe(l, 501.1, 20.4, 26.2),
        0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1),
        1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8),
    ]
}

/// pbrt-v3's `CIE_Y_integral`.
const CIE_Y_INTEGRAL: f64 = 106.856895;

/// XYZ of a spectrum given as a function of wavelength, as pbrt-v3 integrates it (471 samples, 360-830 nm).
pub fn spectrum_to_xyz(f: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut xyz = [0.0; 3];
    for l in 360..=830 {
        let v = f(l as f64);
        let c = cie_xyz(l as f64);
        for k in 0..3 {
            xyz[k] += v * c[k];
        }
    }
    let scale = (830.0 - 360.0) / (CIE_Y_INTEGRAL * 471.0);
    xyz.map(|x| x * scale)
}

/// Linear sRGB (Rec. 709 primaries, D65) of XYZ.
pub fn xyz_to_rgb(xyz: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = xyz;
    [
        3.240479 * x - 1.537150 * y - 0.498535 * z,
        -0.969256 * x + 1.875991 * y + 0.041556 * z,
        0.055648 * x - 0.204043 * y + 1.057311 * z,
    ]
}

/// Planck's law: spectral radiance of a blackbody at temperature `t` (K) and wavelength `l` (nm).
pub fn planck(l: f64, t: f64) -> f64 {
    const C: f64 = 299792458.0;
    const H: f64 = 6.62606957e-34;
    const KB: f64 = 1.3806488e-23;
    let l = l * 1e-9;
    (2.0 * H * C * C) / (l.powi(5) * (((H * C) / (l * KB * t)).exp() - 1.0))
}

/// The blackbody spectrum at `t`, normalised to 1 at its peak.
fn blackbody_normalized(t: f64) -> impl Fn(f64) -> f64 {
    let peak = planck(2.8977721e-3 / t * 1e9, t);
    move |l| planck(l, t) / peak
}

/// pbrt-v3 `blackbody [t scale]` as linear sRGB.
pub fn blackbody_v3(t: f64, scale: f64) -> [f64; 3] {
    xyz_to_rgb(spectrum_to_xyz(blackbody_normalized(t))).map(|c| c * scale)
}

/// pbrt-v4 `blackbody t` as linear sRGB of luminance 1.
pub fn blackbody_v4(t: f64) -> [f64; 3] {
    let xyz = spectrum_to_xyz(blackbody_normalized(t));
    xyz_to_rgb(xyz.map(|c| c / xyz[1]))
}

/// Linear sRGB of a piecewise-linear spectrum given as (wavelength, value) pairs (sorted by wavelength).
pub fn sampled_to_rgb(pairs: &[f64]) -> [f64; 3] {
    let pts: Vec<(f64, f64)> = pairs.chunks_exact(2).map(|c| (c[0], c[1])).collect();
    xyz_to_rgb(spectrum_to_xyz(|l| {
        if pts.is_empty() || l < pts[0].0 || l > pts[pts.len() - 1].0 {
            return 0.0;
        }
        let k = pts.partition_point(|p| p.0 <= l).clamp(1, pts.len() - 1);
        let (a, b) = (pts[k - 1], pts[k]);
        if b.0 == a.0 { a.1 } else { a.1 + (b.1 - a.1) * (l - a.0) / (b.0 - a.0) }
    }))
}

/// A named pbrt spectrum: `Some(metal)` for `metal-X-eta`/`metal-X-k` (the metal's name, to use Prism's RGB
/// index), or a constant for `glass-*` indices.
pub enum NamedSpectrum {
    Metal { metal: &'static str, part: MetalPart },
    Constant(f64),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MetalPart {
    Eta,
    K,
}

pub fn named_spectrum(name: &str) -> Option<NamedSpectrum> {
    let metal = |m: &str| match m {
        "Au" => Some("Au"),
        "Ag" => Some("Ag"),
        "Al" => Some("Al"),
        "Cu" | "CuZn" => Some("Cu"),
        _ => None,
    };
    if let Some(rest) = name.strip_prefix("metal-") {
        let (m, part) = rest.rsplit_once('-')?;
        let part = match part {
            "eta" => MetalPart::Eta,
            "k" => MetalPart::K,
            _ => return None,
        };
        return metal(m).map(|metal| NamedSpectrum::Metal { metal, part });
    }
    let ior = match name {
        "glass-BK7" => 1.5168,
        "glass-BAF10" => 1.6700,
        "glass-FK51A" => 1.4866,
        "glass-LASF9" => 1.8503,
        "glass-F5" | "glass-SF5" => 1.6034,
        "glass-F10" | "glass-SF10" => 1.7283,
        "glass-F11" | "glass-SF11" => 1.7847,
        "fused-silica" | "glass-fused-silica" => 1.4585,
        _ => return None,
    };
    Some(NamedSpectrum::Constant(ior))
}

/// Luminance (Y) of linear sRGB.
pub fn luminance(c: [f64; 3]) -> f64 {
    0.212671 * c[0] + 0.715160 * c[1] + 0.072169 * c[2]
}
