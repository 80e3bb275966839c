//! Any bytes into the glTF/GLB reader (no folder: buffers only in the GLB or data: URIs): it
//! must return a take or an error, never panic or hang; a take must pose and write as BVH.
fn main() {
    afl::fuzz!(|data: &[u8]| {
        if let Ok(read) = bvhview::gltf::load_bytes(data, "fuzz.glb", &Default::default()) {
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
