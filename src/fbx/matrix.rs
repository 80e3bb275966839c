//! ufbx's matrices as glam's.

use glam::{DMat4, DVec4};

/// A ufbx matrix (affine, its columns' fourth row left out) as a 4×4 glam matrix.
pub(super) fn matrix(m: &ufbx::Matrix) -> DMat4 {
    DMat4::from_cols(
        DVec4::new(m.m00, m.m10, m.m20, 0.0),
        DVec4::new(m.m01, m.m11, m.m21, 0.0),
        DVec4::new(m.m02, m.m12, m.m22, 0.0),
        DVec4::new(m.m03, m.m13, m.m23, 1.0),
    )
}
