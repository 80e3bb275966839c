//! Any bytes into the FBX reader (ufbx with bvhview's limits): it must return a take or an
//! error, never panic, abort or hang; a take must pose and write as BVH.
fn main() {
    afl::fuzz!(|data: &[u8]| {
        if let Ok(read) = bvhview::fbx::load_bytes(data, "fuzz.fbx", &bvhview::take::OpenOptions::new().threads(1)) {
            let last = read.motion.frame_count().saturating_sub(1);
            let _ = bvhview::model::pose::world_positions(
                &read.skeleton,
                read.motion.frame(last),
                Default::default(),
            );
            let _ = bvhview::bvh::writer::to_string(&read.skeleton, &read.motion);
        }
    });
}
