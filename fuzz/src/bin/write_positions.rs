//! The positions export (CSV and JSON), fed what the BVH loader makes of any bytes: whatever it
//! writes must parse back, every number finite, one row per frame and point; whatever it
//! refuses must be refused before the header.
use bvhview::positions::{PositionsFormat, PositionsOptions};
use bvhview_fuzz::split;

fn main() {
    afl::fuzz!(|data: &[u8]| {
        let (choice, bytes) = split(data);
        let Ok(bvh) = bvhview::bvh::load_bytes(bytes, "fuzz.bvh") else {
            return;
        };
        let frames = bvh.motion.frame_count().max(1);
        let options = PositionsOptions {
            format: if choice & 1 == 0 {
                PositionsFormat::Csv
            } else {
                PositionsFormat::Json
            },
            offset_mode: if choice & 2 == 0 {
                bvhview::model::pose::OffsetMode::Replace
            } else {
                bvhview::model::pose::OffsetMode::Add
            },
            left_handed: choice & 4 != 0,
            scale: [1.0, 100.0, 1e30, -0.001][usize::from(choice >> 3) % 4],
        };
        let mut out = Vec::new();
        let points = bvhview::positions::export_points(&bvh.skeleton).len();
        match bvhview::positions::write_positions(
            &mut out,
            &bvh.skeleton,
            &bvh.motion,
            0..frames,
            &options,
        ) {
            // A refusal comes before the header of a short take; a long one may have begun.
            Err(_) => assert!(
                frames > 2048 || out.is_empty(),
                "a refused short export wrote {} bytes",
                out.len()
            ),
            Ok(()) => {
                let text = String::from_utf8(out).expect("the export is UTF-8");
                match options.format {
                    PositionsFormat::Csv => {
                        let mut lines = text.lines();
                        assert_eq!(lines.next(), Some("frame,joint,x,y,z"));
                        let mut rows = 0;
                        for line in lines {
                            let fields: Vec<&str> = line.rsplitn(4, ',').collect();
                            assert_eq!(fields.len(), 4, "{line}");
                            for number in &fields[..3] {
                                let value: f32 =
                                    number.parse().unwrap_or_else(|_| panic!("{line}"));
                                assert!(value.is_finite(), "{line}");
                            }
                            rows += 1;
                        }
                        assert_eq!(rows, frames * points);
                    }
                    PositionsFormat::Json => {
                        let value: serde_json::Value =
                            serde_json::from_str(&text).unwrap_or_else(|e| panic!("JSON: {e}"));
                        let written = value["frames"].as_array().expect("frames").len();
                        assert_eq!(written, frames);
                    }
                }
            }
        }
    });
}
