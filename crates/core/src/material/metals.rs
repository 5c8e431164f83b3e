//! Named conductors: complex indices of refraction `eta + i k` as one linear-sRGB triple each. `Au` carries the
//! exact numbers Mitsuba 3.9 uses in RGB mode (`../shared/refs/cornell_rough.md`: its spectral data reduced by
//! `spectrum_list_to_srgb`); the others are the RGB values commonly used by RGB renderers (pbrt-v3's scenes), good
//! to about a percent of reflectance.

use glam::Vec3;

/// `(name, eta, k)`. (Au: Mitsuba's float32 values, written out in full.)
#[allow(clippy::excessive_precision)]
pub const METALS: [(&str, [f32; 3], [f32; 3]); 4] = [
    ("Au", [0.143_035_98, 0.375_307_08, 1.442_045_3], [3.982_996_9, 2.385_556_5, 1.603_359_2]),
    ("Ag", [0.155_265, 0.116_723, 0.138_342], [4.828_35, 3.122_25, 2.146_96]),
    ("Al", [1.657_46, 0.880_369, 0.521_229], [9.223_87, 6.269_52, 4.837]),
    ("Cu", [0.200_438, 0.924_033, 1.102_21], [3.912_95, 2.452_85, 2.142_19]),
];

/// The complex index of a named metal (case-sensitive chemical symbol).
pub fn metal(name: &str) -> Option<(Vec3, Vec3)> {
    METALS.iter().find(|(n, ..)| *n == name).map(|(_, e, k)| (Vec3::from(*e), Vec3::from(*k)))
}

/// The names, for error messages.
pub fn metal_names() -> String {
    METALS.iter().map(|(n, ..)| *n).collect::<Vec<_>>().join(", ")
}
