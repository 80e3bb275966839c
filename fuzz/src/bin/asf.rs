//! Any text into the ASF loader, and what loads into the skeleton builder.
fn main() {
    afl::fuzz!(|data: &[u8]| {
        let text = String::from_utf8_lossy(data);
        if let Ok(asf) = bvhview::acclaim::asf::parse_asf(&text, "fuzz.asf") {
            let (skeleton, _) = asf.to_skeleton();
            let _ = bvhview::model::pose::world_positions(&skeleton, &[], Default::default());
            let _ = bvhview::bvh::print::print(&skeleton);
        }
    });
}
