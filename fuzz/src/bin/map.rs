//! Any bytes as a retarget map file (TOML or JSON), then applied to a real pair of skeletons
//! (a CMU walk's first frames onto a Second Life take, both of tests/data): the parser must
//! give pairs or an error with a line and column, and the map must be refused with a reason or
//! retarget the take, never panic.
use bvhview::bvh::loader::load_bytes;
use bvhview::retarget::{Target, parse_map};

const SOURCE: &str = include_str!("../../../tests/data/bvh/bvhparser_walk_01.bvh");
const TARGET: &str = include_str!("../../../tests/data/bvh/opencollar_oc_stand_boy01.bvh");

fn main() {
    let source = load_bytes(SOURCE.as_bytes(), "source.bvh").expect("a real take");
    let source_motion = bvhview::edit::trim(&source.motion, 0..4);
    let target = load_bytes(TARGET.as_bytes(), "target.bvh").expect("a real take");
    let onto = Target::new("target.bvh".into(), target.skeleton, &target.motion);
    afl::fuzz!(|data: &[u8]| {
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        match parse_map(text, "fuzz.toml") {
            Ok(pairs) => {
                let _ = onto.apply("source.bvh", &source.skeleton, &source_motion, &pairs, Default::default(), 1);
            }
            Err(error) => assert!(matches!(error, bvhview::Error::Parse { .. }), "{error}"),
        }
    });
}
