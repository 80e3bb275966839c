//! The BVH writer, fed what the BVH loader makes of any bytes after an edit the first byte
//! picks: whatever the writer accepts must load back with the same joints and bit-identical
//! values, and whatever it refuses must be refused before a byte is written.
use bvhview_fuzz::edited_take;

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let Some((_, skeleton, motion)) = edited_take(data) else {
            return;
        };
        let mut written = Vec::new();
        match bvhview::bvh::writer::write_bvh(&mut written, &skeleton, &motion) {
            Err(_) => assert!(
                written.is_empty(),
                "a refused take wrote {} bytes",
                written.len()
            ),
            Ok(()) => {
                let back = bvhview::bvh::load_bytes(&written, "written.bvh")
                    .unwrap_or_else(|e| panic!("the writer wrote a file its loader refuses: {e}"));
                assert_eq!(back.skeleton.joints.len(), skeleton.joints.len());
                let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&back.motion.data), bits(&motion.data));
                for (a, b) in back.skeleton.joints.iter().zip(&skeleton.joints) {
                    assert_eq!(
                        a.offset.to_array().map(f32::to_bits),
                        b.offset.to_array().map(f32::to_bits)
                    );
                    assert_eq!(a.channels, b.channels);
                }
            }
        }
    });
}
