//! Any text into the AMC loader, against a real CMU skeleton (embedded at build time).
fn main() {
    let asf_text = include_str!("../../../tests/data/asf_amc/heiden_12.asf");
    let asf =
        bvhview::acclaim::asf::parse_asf(asf_text, "heiden_12.asf").expect("the real ASF loads");
    let (skeleton, maps) = asf.to_skeleton();
    let channels = skeleton.channel_count();
    afl::fuzz!(|data: &[u8]| {
        let text = String::from_utf8_lossy(data);
        if let Ok(motion) =
            bvhview::acclaim::amc::parse_amc(&text, "fuzz.amc", &maps, channels, true, 0.01)
        {
            if motion.frame_count() > 0 {
                let _ =
                    bvhview::model::pose::world_positions(&skeleton, motion.frame(0), Default::default());
            }
            let _ = bvhview::edit::bake_axes(&skeleton, &motion);
        }
    });
}
