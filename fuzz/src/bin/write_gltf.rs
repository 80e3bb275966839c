//! The glTF writer, fed what the BVH loader makes of any bytes after an edit the first byte
//! picks: whatever it writes must be JSON that glTF's own schema crate reads back, with no
//! `null` where a number belongs.
use bvhview_fuzz::edited_take;

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let Some((choice, skeleton, motion)) = edited_take(data) else {
            return;
        };
        let mode = if choice & 0x80 != 0 {
            bvhview::model::pose::OffsetMode::Add
        } else {
            bvhview::model::pose::OffsetMode::Replace
        };
        let container = bvhview::gltf::Container::Gltf;
        if let Ok(bytes) =
            bvhview::gltf::to_gltf(&skeleton, &motion, mode, container, choice & 0x40 != 0)
        {
            let root = gltf_json::Root::from_slice(&bytes)
                .unwrap_or_else(|e| panic!("the glTF written does not read back: {e}"));
            assert_eq!(root.nodes.len() >= skeleton.joints.len(), true);
            for node in &root.nodes {
                if let Some(t) = node.translation {
                    assert!(t.iter().all(|v| v.is_finite()), "{t:?}");
                }
            }
            // No `null` anywhere in the JSON (a number that was not finite); the base64 data
            // may spell "null" by chance, so the values are walked, not the text searched.
            let json: serde_json::Value = serde_json::from_slice(&bytes).expect("glTF is JSON");
            assert!(!has_null(&json), "a null in the glTF");
        }
    });
}

fn has_null(value: &serde_json::Value) -> bool {
    match value {
        serde_json::Value::Null => true,
        serde_json::Value::Array(items) => items.iter().any(has_null),
        serde_json::Value::Object(fields) => fields.values().any(has_null),
        _ => false,
    }
}
