//! Scene transform operations to matrices, with validation (finite, invertible, affine).

use super::schema::TransformOp;
use glam::{Affine3A, Mat3, Mat4, Quat, Vec3};
use prism_core::error::{PrismError, Result};

/// Compose a list of operations left to right as a matrix product: `[A, B]` maps `p` to `A(B(p))`.
pub fn compose(ops: &[TransformOp], context: &str) -> Result<Affine3A> {
    let mut m = Affine3A::IDENTITY;
    for op in ops {
        m *= op_matrix(op, context)?;
    }
    prism_core::math::check_affine(&m, context)?;
    Ok(m)
}

fn bad(context: &str, msg: impl Into<String>) -> PrismError {
    PrismError::scene(context, msg)
}

fn finite(v: &[f32], what: &str, context: &str) -> Result<()> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(bad(context, format!("{what} contains NaN or infinity: {v:?}")))
    }
}

fn op_matrix(op: &TransformOp, context: &str) -> Result<Affine3A> {
    Ok(match op {
        TransformOp::Translate(t) => {
            finite(t, "Translate", context)?;
            Affine3A::from_translation(Vec3::from(*t))
        }
        TransformOp::Scale(s) => {
            finite(s, "Scale", context)?;
            if s.contains(&0.0) {
                return Err(bad(
                    context,
                    format!("Scale {s:?} has a zero factor (the transform would not be invertible)"),
                ));
            }
            Affine3A::from_scale(Vec3::from(*s))
        }
        TransformOp::UniformScale(s) => {
            finite(&[*s], "UniformScale", context)?;
            if *s == 0.0 {
                return Err(bad(context, "UniformScale is zero (the transform would not be invertible)"));
            }
            Affine3A::from_scale(Vec3::splat(*s))
        }
        TransformOp::Rotate { axis, degrees } => {
            finite(axis, "Rotate axis", context)?;
            finite(&[*degrees], "Rotate degrees", context)?;
            let a = prism_core::math::unit_vector(Vec3::from(*axis))
                .ok_or_else(|| bad(context, "Rotate axis is the zero vector"))?;
            Affine3A::from_quat(Quat::from_axis_angle(a, degrees.to_radians()))
        }
        TransformOp::Euler(e) => {
            finite(e, "Euler", context)?;
            let r = Mat3::from_rotation_z(e[2].to_radians())
                * Mat3::from_rotation_y(e[1].to_radians())
                * Mat3::from_rotation_x(e[0].to_radians());
            Affine3A::from_mat3(r)
        }
        TransformOp::Matrix(rows) => {
            let flat: Vec<f32> = rows.iter().flatten().copied().collect();
            finite(&flat, "Matrix", context)?;
            if rows[3] != [0.0, 0.0, 0.0, 1.0] {
                return Err(bad(context, format!("Matrix last row must be [0, 0, 0, 1] (affine), got {:?}", rows[3])));
            }
            let m = Mat4::from_cols_array_2d(rows).transpose();
            Affine3A::from_mat4(m)
        }
    })
}
