//! Quaternions made continuous along a clip (`--quat-continuous`).

/// Each joint's quaternions (w, x, y, z per frame, `rotated` joints per frame) made continuous
/// along time: a frame's quaternion is negated where it points away from the previous frame's
/// (the same rotation either way).
pub(super) fn continuous_quaternions(rotations: &mut [f32], rotated: usize) {
    let stride = rotated * 4;
    if stride == 0 {
        return;
    }
    for f in 1..rotations.len() / stride {
        let (before, after) = rotations.split_at_mut(f * stride);
        let previous = &before[(f - 1) * stride..];
        for (q, p) in after[..stride].chunks_mut(4).zip(previous.chunks(4)) {
            let dot: f32 = q.iter().zip(p).map(|(a, b)| a * b).sum();
            if dot < 0.0 {
                q.iter_mut().for_each(|v| *v = -*v);
            }
        }
    }
}
