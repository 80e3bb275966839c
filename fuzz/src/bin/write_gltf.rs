//! The glTF writer, fed what the BVH loader makes of any bytes after an edit the first byte
//! picks: whatever it writes must be JSON that glTF's own schema crate reads back, with no
//! `null` where a number belongs.
use bvhview_fuzz::{edited, split};

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let (choice, bytes) = split(data);
        let Ok(bvh) = bvhview::bvh::load_bytes(bytes, "fuzz.bvh") else {
            return;
        };
        let Some((skeleton, motion)) = edited(choice, bvh.skeleton, bvh.motion) else {
            return;
        };
        let mode = if choice & 0x80 != 0 {
            bvhview::pose::OffsetMode::Add
        } else {
            bvhview::pose::OffsetMode::Replace
        };
        let container = bvhview::gltf::Container::Gltf;
        if let Ok(bytes) = bvhview::gltf::to_gltf(&skeleton, &motion, mode, container, choice & 0x40 != 0) {
            let root = gltf_json::Root::from_slice(&bytes)
                .unwrap_or_else(|e| panic!("the glTF written does not read back: {e}"));
            assert_eq!(root.nodes.len() >= skeleton.joints.len(), true);
            for node in &root.nodes {
                if let Some(t) = node.translation {
                    assert!(t.iter().all(|v| v.is_finite()), "{t:?}");
                }
            }
            let text = String::from_utf8(bytes).expect("glTF JSON is UTF-8");
            assert!(!text.contains("null"), "a null in the glTF");
        }
    });
}
