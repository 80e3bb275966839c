//! Any bytes into the fbx character reader (skeleton, take and skinned mesh): it must return a
//! character or an error, never panic or hang; a character's mesh must be consistent and skin
//! at its last frame.
fn main() {
    afl::fuzz!(|data: &[u8]| {
        if let Ok((read, mesh)) = bvhview::fbx::load_character_bytes(data, "fuzz.character", &bvhview::take::OpenOptions::new().threads(1)) {
            mesh.check().expect("a mesh the reader hands over is consistent");
            let last = read.motion.frame_count().saturating_sub(1);
            let mut world = Vec::new();
            bvhview::model::pose::world_matrices(
                &read.skeleton,
                read.motion.frame(last),
                Default::default(),
                &mut world,
            );
            if mesh.bones.iter().all(|b| b.joint.is_none_or(|j| j < world.len())) {
                let (mut positions, mut normals) = (Vec::new(), Vec::new());
                mesh.deform(&world, &mut positions, &mut normals);
            } else {
                panic!("a bone names a joint past the skeleton");
            }
        }
    });
}
