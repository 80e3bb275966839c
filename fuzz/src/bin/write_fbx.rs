//! The FBX writer, fed what the BVH loader makes of any bytes after an edit the first byte
//! picks: whatever it writes, bvhview's own reader (ufbx) must read back with the same joints,
//! each within 1e-4 of the figure's size of where it was on the last frame; what it refuses
//! writes nothing.
use bvhview_fuzz::edited_take;

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let Some((_, skeleton, motion)) = edited_take(data) else {
            return;
        };
        let take = bvhview::Take::new(skeleton, motion, "fuzz".to_string());
        let Ok(written) = take.fbx() else {
            return;
        };
        let back = bvhview::OpenOptions::new()
            .open_bytes(&written.bytes, "fuzz.fbx")
            .unwrap_or_else(|e| panic!("the FBX written does not read back: {e}"));
        assert_eq!(back.skeleton.joints.len(), take.skeleton.joints.len());
        let stance = take.stance(take.offset_mode);
        // In 64 bits: a rotation channel may hold 1e8 degrees, whose 32-bit sine is off by more
        // than the check allows (ufbx works in 64 bits).
        let last = |t: &bvhview::Take| {
            let row = match t.motion.frame_count() {
                0 => &[][..],
                n => t.motion.frame(n - 1),
            };
            let mut out = Vec::new();
            bvhview::model::pose::world_transforms_f64(&t.skeleton, row, t.offset_mode, &mut out);
            out.into_iter()
                .map(|(_, p)| p.as_vec3())
                .collect::<Vec<_>>()
        };
        let size = (stance.size * stance.units.metres).max(1e-6);
        for (want, got) in last(&take).iter().zip(last(&back)) {
            let mut want = *want * stance.units.metres;
            if stance.up == bvhview::model::pose::Up::Z {
                want = glam::Vec3::new(want.x, want.z, -want.y);
            }
            let error = (want - got).length() / size;
            assert!(error <= 1e-4 || !error.is_finite(), "{want} vs {got}");
        }
    });
}
