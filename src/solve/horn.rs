//! Horn's quaternion method: the one rotation that best lays several directions onto theirs
//! (the hips onto both thighs and the spine, the chest onto the neck and both clavicles).

use glam::{DQuat, DVec3};

/// The rotation that best turns each `from` onto its `to` (unit directions, equal weights):
/// Horn's quaternion method, the eigenvector of the largest eigenvalue of a symmetric 4 × 4
/// matrix. Exact when the directions agree with one rotation.
pub(super) fn best_rotation(pairs: &[(DVec3, DVec3)]) -> DQuat {
    // S[a][b] = Σ from_a · to_b.
    let mut s = [[0.0f64; 3]; 3];
    for &(from, to) in pairs {
        let (from, to) = (from.normalize(), to.normalize());
        for a in 0..3 {
            for b in 0..3 {
                s[a][b] += from[a] * to[b];
            }
        }
    }
    let [[xx, xy, xz], [yx, yy, yz], [zx, zy, zz]] = s;
    let n = [
        [xx + yy + zz, yz - zy, zx - xz, xy - yx],
        [yz - zy, xx - yy - zz, xy + yx, zx + xz],
        [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
        [xy - yx, zx + xz, yz + zy, -xx - yy + zz],
    ];
    let [w, x, y, z] = largest_eigenvector(n);
    DQuat::from_xyzw(x, y, z, w).normalize()
}

/// The eigenvector of the largest eigenvalue of a symmetric 4 × 4 matrix, by cyclic Jacobi
/// rotations (exact to rounding for these sizes in a few sweeps).
fn largest_eigenvector(mut a: [[f64; 4]; 4]) -> [f64; 4] {
    let mut v = [[0.0f64; 4]; 4];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _ in 0..32 {
        let off: f64 = (0..4)
            .flat_map(|p| ((p + 1)..4).map(move |q| (p, q)))
            .map(|(p, q)| a[p][q] * a[p][q])
            .sum();
        if off < 1e-30 {
            break;
        }
        for p in 0..4 {
            for q in (p + 1)..4 {
                if a[p][q].abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for row in a.iter_mut() {
                    let (akp, akq) = (row[p], row[q]);
                    row[p] = c * akp - s * akq;
                    row[q] = s * akp + c * akq;
                }
                let (row_p, row_q) = (a[p], a[q]);
                for k in 0..4 {
                    a[p][k] = c * row_p[k] - s * row_q[k];
                    a[q][k] = s * row_p[k] + c * row_q[k];
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    let best = (0..4)
        .max_by(|&i, &j| a[i][i].total_cmp(&a[j][j]))
        .unwrap_or(0);
    [v[0][best], v[1][best], v[2][best], v[3][best]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_best_rotation_recovers_a_rotation_from_three_directions() {
        let turn = DQuat::from_euler(glam::EulerRot::YXZ, 1.1, -0.4, 2.7);
        let from = [
            DVec3::X,
            DVec3::new(0.3, 1.0, -0.2),
            DVec3::new(-0.5, -0.1, 0.9),
        ];
        let pairs: Vec<(DVec3, DVec3)> = from.iter().map(|&f| (f, turn * f)).collect();
        let found = best_rotation(&pairs);
        for &(f, t) in &pairs {
            assert!((found * f - t).length() < 1e-12, "{} {}", found * f, t);
        }
        // Two directions fix it too; a half turn is found as well as a small one.
        let half = DQuat::from_axis_angle(DVec3::Y, std::f64::consts::PI);
        let pairs = [(DVec3::X, half * DVec3::X), (DVec3::Z, half * DVec3::Z)];
        let found = best_rotation(&pairs);
        assert!((found * DVec3::X - half * DVec3::X).length() < 1e-12);
        assert!((found * DVec3::Z - half * DVec3::Z).length() < 1e-12);
    }
}
