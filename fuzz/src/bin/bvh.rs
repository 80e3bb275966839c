//! Any bytes into the BVH loader: it must return a value or an error, never panic or hang.
fn main() {
    afl::fuzz!(|data: &[u8]| {
        if let Ok(bvh) = bvhview::bvh::load_bytes(data, "fuzz.bvh") {
            // What loaded must also print, write and pose without trouble.
            let _ = bvhview::bvh::print::print(&bvh.skeleton);
            let _ = bvhview::bvh::writer::to_string(&bvh.skeleton, &bvh.motion);
            if bvh.motion.frame_count() > 0 {
                let _ = bvhview::model::pose::world_positions(
                    &bvh.skeleton,
                    bvh.motion.frame(0),
                    Default::default(),
                );
            }
        }
    });
}
