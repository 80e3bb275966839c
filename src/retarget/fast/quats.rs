//! Quaternions and points in lanes: eight frames' rotations and positions side by side.

use crate::retarget::fast::lanes::{LANES, Lanes, lanes, mask};
use crate::retarget::fast::trig::{atan2, sin_cos};
use glam::{DQuat, DVec3};

/// A quaternion per lane.
#[derive(Clone, Copy, Debug)]
pub(super) struct Quats {
    pub(super) x: Lanes,
    pub(super) y: Lanes,
    pub(super) z: Lanes,
    pub(super) w: Lanes,
}

/// A point per lane.
#[derive(Clone, Copy, Debug)]
pub(super) struct Points {
    pub(super) x: Lanes,
    pub(super) y: Lanes,
    pub(super) z: Lanes,
}

impl Points {
    pub(super) fn splat(v: DVec3) -> Points {
        Points {
            x: [v.x; LANES],
            y: [v.y; LANES],
            z: [v.z; LANES],
        }
    }

    pub(super) fn get(&self, l: usize) -> DVec3 {
        DVec3::new(self.x[l], self.y[l], self.z[l])
    }

    pub(super) fn set(&mut self, l: usize, v: DVec3) {
        (self.x[l], self.y[l], self.z[l]) = (v.x, v.y, v.z);
    }

    #[inline(always)]
    pub(super) fn add(&self, b: &Points) -> Points {
        Points {
            x: lanes(|l| self.x[l] + b.x[l]),
            y: lanes(|l| self.y[l] + b.y[l]),
            z: lanes(|l| self.z[l] + b.z[l]),
        }
    }
}

impl Quats {
    pub(super) const IDENTITY: Quats = Quats {
        x: [0.0; LANES],
        y: [0.0; LANES],
        z: [0.0; LANES],
        w: [1.0; LANES],
    };

    pub(super) fn splat(q: DQuat) -> Quats {
        Quats {
            x: [q.x; LANES],
            y: [q.y; LANES],
            z: [q.z; LANES],
            w: [q.w; LANES],
        }
    }

    pub(super) fn get(&self, l: usize) -> DQuat {
        DQuat::from_xyzw(self.x[l], self.y[l], self.z[l], self.w[l])
    }

    pub(super) fn set(&mut self, l: usize, q: DQuat) {
        (self.x[l], self.y[l], self.z[l], self.w[l]) = (q.x, q.y, q.z, q.w);
    }

    #[inline(always)]
    pub(super) fn conjugate(&self) -> Quats {
        Quats {
            x: lanes(|l| -self.x[l]),
            y: lanes(|l| -self.y[l]),
            z: lanes(|l| -self.z[l]),
            w: self.w,
        }
    }

    /// `self · b`, glam's `DQuat::mul_quat` term for term.
    #[inline(always)]
    pub(super) fn mul(&self, b: &Quats) -> Quats {
        let a = self;
        Quats {
            x: lanes(|l| a.w[l] * b.x[l] + a.x[l] * b.w[l] + a.y[l] * b.z[l] - a.z[l] * b.y[l]),
            y: lanes(|l| a.w[l] * b.y[l] - a.x[l] * b.z[l] + a.y[l] * b.w[l] + a.z[l] * b.x[l]),
            z: lanes(|l| a.w[l] * b.z[l] + a.x[l] * b.y[l] - a.y[l] * b.x[l] + a.z[l] * b.w[l]),
            w: lanes(|l| a.w[l] * b.w[l] - a.x[l] * b.x[l] - a.y[l] * b.y[l] - a.z[l] * b.z[l]),
        }
    }

    /// `self · (axis · s, c)` (`s`, `c`: sine and cosine of half the angle): [`Quats::mul`] with
    /// its products by the axis's zeros left out, which changes no value (only, at most, the sign
    /// of a zero).
    #[inline(always)]
    pub(super) fn times_axis(&self, axis: usize, s: &Lanes, c: &Lanes) -> Quats {
        let Quats { x, y, z, w } = self;
        match axis {
            0 => Quats {
                x: lanes(|l| w[l] * s[l] + x[l] * c[l]),
                y: lanes(|l| y[l] * c[l] + z[l] * s[l]),
                z: lanes(|l| z[l] * c[l] - y[l] * s[l]),
                w: lanes(|l| w[l] * c[l] - x[l] * s[l]),
            },
            1 => Quats {
                x: lanes(|l| x[l] * c[l] - z[l] * s[l]),
                y: lanes(|l| w[l] * s[l] + y[l] * c[l]),
                z: lanes(|l| x[l] * s[l] + z[l] * c[l]),
                w: lanes(|l| w[l] * c[l] - y[l] * s[l]),
            },
            _ => Quats {
                x: lanes(|l| x[l] * c[l] + y[l] * s[l]),
                y: lanes(|l| y[l] * c[l] - x[l] * s[l]),
                z: lanes(|l| w[l] * s[l] + z[l] * c[l]),
                w: lanes(|l| w[l] * c[l] - z[l] * s[l]),
            },
        }
    }

    /// `v` turned by this quaternion, glam's `DQuat::mul_vec3` term for term.
    #[inline(always)]
    pub(super) fn rotate(&self, v: &Points) -> Points {
        let Quats { x, y, z, w } = self;
        let b2 = lanes(|l| x[l] * x[l] + y[l] * y[l] + z[l] * z[l]);
        let k = lanes(|l| w[l] * w[l] - b2[l]);
        let d = lanes(|l| (v.x[l] * x[l] + v.y[l] * y[l] + v.z[l] * z[l]) * 2.0);
        let w2 = lanes(|l| w[l] * 2.0);
        Points {
            x: lanes(|l| v.x[l] * k[l] + x[l] * d[l] + (y[l] * v.z[l] - v.y[l] * z[l]) * w2[l]),
            y: lanes(|l| v.y[l] * k[l] + y[l] * d[l] + (z[l] * v.x[l] - v.z[l] * x[l]) * w2[l]),
            z: lanes(|l| v.z[l] * k[l] + z[l] * d[l] + (x[l] * v.y[l] - v.x[l] * y[l]) * w2[l]),
        }
    }

    /// The Euler angles in degrees of this rotation with the axes `[i, j, k]` of a rotation order
    /// (file order) and their `sign` (+1 when they turn as x, y, z do): [`crate::model::euler::split`]
    /// with no previous frame, step for step: the matrix of the normalised quaternion (glam's
    /// `DMat3::from_quat`), the middle angle against the length of the other two, the third
    /// read off it away from the lock (else 0), the first from the rotation with the third
    /// taken off.
    #[inline(always)]
    pub(super) fn euler_degrees(&self, ([i, j, k], sign): ([usize; 3], f64)) -> [Lanes; 3] {
        let length = lanes(|l| {
            let q = self;
            (q.x[l] * q.x[l] + q.y[l] * q.y[l] + q.z[l] * q.z[l] + q.w[l] * q.w[l]).sqrt()
        });
        let unit = Quats {
            x: lanes(|l| self.x[l] * (1.0 / length[l])),
            y: lanes(|l| self.y[l] * (1.0 / length[l])),
            z: lanes(|l| self.z[l] * (1.0 / length[l])),
            w: lanes(|l| self.w[l] * (1.0 / length[l])),
        };
        let Quats { x, y, z, w } = &unit;
        let x2 = lanes(|l| x[l] + x[l]);
        let y2 = lanes(|l| y[l] + y[l]);
        let z2 = lanes(|l| z[l] + z[l]);
        let (xx, xy, xz) = (
            lanes(|l| x[l] * x2[l]),
            lanes(|l| x[l] * y2[l]),
            lanes(|l| x[l] * z2[l]),
        );
        let (yy, yz, zz) = (
            lanes(|l| y[l] * y2[l]),
            lanes(|l| y[l] * z2[l]),
            lanes(|l| z[l] * z2[l]),
        );
        let (wx, wy, wz) = (
            lanes(|l| w[l] * x2[l]),
            lanes(|l| w[l] * y2[l]),
            lanes(|l| w[l] * z2[l]),
        );
        // Column-major: m[column][row].
        let m: [[Lanes; 3]; 3] = [
            [
                lanes(|l| 1.0 - (yy[l] + zz[l])),
                lanes(|l| xy[l] + wz[l]),
                lanes(|l| xz[l] - wy[l]),
            ],
            [
                lanes(|l| xy[l] - wz[l]),
                lanes(|l| 1.0 - (xx[l] + zz[l])),
                lanes(|l| yz[l] + wx[l]),
            ],
            [
                lanes(|l| xz[l] + wy[l]),
                lanes(|l| yz[l] - wx[l]),
                lanes(|l| 1.0 - (xx[l] + yy[l])),
            ],
        ];
        let cos_middle = lanes(|l| (m[i][i][l] * m[i][i][l] + m[j][i][l] * m[j][i][l]).sqrt());
        let middle = atan2(&lanes(|l| sign * m[k][i][l]), &cos_middle);
        let free = mask(|l| cos_middle[l] > crate::model::euler::LOCK);
        let third = atan2(&lanes(|l| -sign * m[j][i][l]), &m[i][i]);
        let third = lanes(|l| if free[l] { third[l] } else { 0.0 });
        // Column j of the rotation with the third angle taken off: m · R_k(−third) · e_j.
        let (mut sin, mut cos) = ([0.0; LANES], [0.0; LANES]);
        sin_cos(&third, &mut sin, &mut cos);
        let turned = lanes(|l| sign * sin[l]);
        let left_k = lanes(|l| m[i][k][l] * turned[l] + m[j][k][l] * cos[l]);
        let left_j = lanes(|l| m[i][j][l] * turned[l] + m[j][j][l] * cos[l]);
        let first = atan2(&lanes(|l| sign * left_k[l]), &left_j);
        let degrees = |v: Lanes| lanes(|l| v[l].to_degrees());
        [degrees(first), degrees(middle), degrees(third)]
    }
}
