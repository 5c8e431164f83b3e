//! Validity of an entity's composed transform: finite and invertible (normals and object-space intersection need
//! the inverse).

use crate::error::{PrismError, Result};
use glam::Affine3A;

/// Reject transforms that cannot be inverted (normals and object-space intersection need the inverse).
pub fn check_affine(m: &Affine3A, context: &str) -> Result<()> {
    let det = m.matrix3.determinant();
    if !det.is_finite() || !m.translation.is_finite() {
        return Err(PrismError::scene(context, "transform is not finite"));
    }
    let scale = m.matrix3.x_axis.length() * m.matrix3.y_axis.length() * m.matrix3.z_axis.length();
    if det == 0.0 || det.abs() <= 1e-12 * scale {
        return Err(PrismError::scene(context, "transform is singular (it flattens space)"));
    }
    Ok(())
}
