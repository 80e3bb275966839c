//! Broken input gets `path:line:column: message`; odd but valid input loads.

use crate::common;
use common::*;

/// Every file in bvh_malformed (tests/data and ../shared/data hold the same ten) with the exact
/// error it gets (None: it loads).
const MALFORMED: &[(&str, Option<&str>)] = &[
    (
        "dali_test-empty.bvh",
        Some("1:1: expected HIERARCHY, found end of file"),
    ),
    (
        "dali_test-invalid-hierarchy0.bvh",
        Some("15:1: expected '}' to close 'root' before MOTION, found 'MOTION'"),
    ),
    (
        "dali_test-invalid-hierarchy1.bvh",
        Some("3:3: expected '{' after 'root', found 'OFFSET'"),
    ),
    (
        "dali_test-invalid-hierarchy2.bvh",
        Some("3:3: expected '{' after 'root', found 'OFFSET'"),
    ),
    (
        "dali_test-invalid-hierarchy3.bvh",
        Some("15:1: expected '}' to close 'root' before MOTION, found 'MOTION'"),
    ),
    (
        "dali_test-invalid-hierarchy4.bvh",
        Some("11:7: expected '{' after 'Site', found 'OFFSET'"),
    ),
    (
        "dali_test-invalid-hierarchy5.bvh",
        Some("11:7: expected '{' after 'Site', found 'OFFSET'"),
    ),
    (
        "dali_test-invalid-motion0.bvh",
        Some("21:51: expected 3 frames as Frames: says (line 17), found 2: the file ends"),
    ),
    ("dali_test-invalid-motion1.bvh", None),
    ("dali_test.bvh", None),
];

#[test]
fn every_malformed_repository_file_fails_where_it_breaks() {
    check_malformed(&repo_data("bvh_malformed"));
}

#[test]
#[ignore = "needs ../shared/data; scripts/test.sh runs it when the folder is there"]
fn every_malformed_whole_corpus_file_fails_where_it_breaks() {
    check_malformed(&shared_data("bvh_malformed"));
}

fn check_malformed(folder: &std::path::Path) {
    let files = files_in(folder, "bvh");
    assert_eq!(
        files.len(),
        MALFORMED.len(),
        "a file in bvh_malformed has no expectation here"
    );
    for (name, expected) in MALFORMED {
        let path = folder.join(name);
        let result = bvhview::bvh::load_file(&path, Default::default());
        match (expected, result) {
            (Some(message), Err(error)) => {
                assert_eq!(error.to_string(), format!("{}:{message}", path.display()));
                assert!(error.is_the_callers(), "exit 2: the input's fault");
            }
            (None, Ok(bvh)) => assert_eq!(bvh.skeleton.joints.len(), 3, "{name}"),
            (Some(_), Ok(_)) => panic!("{name} loaded"),
            (None, Err(e)) => panic!("{e}"),
        }
    }
    let extra = bvhview::bvh::load_file(
        &folder.join("dali_test-invalid-motion1.bvh"),
        Default::default(),
    );
    let extra = extra.unwrap();
    assert_eq!(extra.motion.frame_count(), 1);
    assert_eq!(extra.warnings.len(), 1);
}

const TWO_JOINTS: &str = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition \
Zposition Zrotation Xrotation Yrotation\n\tJOINT Chest\n\t{\n\t\tOFFSET 0 10 0\n\t\tCHANNELS 3 \
Zrotation Xrotation Yrotation\n\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 0 5 0\n\t\t}\n\t}\n}\nMOTION\n\
Frames: 2\nFrame Time: .5\n1 2 3 4 5 6 7 8 9\n-1 -2 -3 -4 -5 -6 -7 -8 -9e0\n";

#[test]
fn the_same_file_reads_the_same_with_any_line_ending_tabs_or_spaces() {
    let reference = load_text(TWO_JOINTS).unwrap();
    assert_eq!(reference.motion.frame_time, 0.5);
    assert_eq!(reference.motion.frame(1)[8], -9.0);
    let variants = [
        TWO_JOINTS.replace('\n', "\r\n"),
        TWO_JOINTS.replace('\n', "\r"),
        TWO_JOINTS.replace('\t', "    "),
        // Mixed in one file: CRLF in the hierarchy, CR then LF in the motion.
        TWO_JOINTS.replacen('\n', "\r\n", 9).replacen('\n', "\r", 3),
        format!("\u{feff}{TWO_JOINTS}"),
        TWO_JOINTS.replace("\n\t{", " {"),
    ];
    for text in &variants {
        let bvh = load_text(text).unwrap_or_else(|e| panic!("{e}\n{text:?}"));
        assert_eq!(bvh.skeleton, reference.skeleton, "{text:?}");
        assert_eq!(bvh.motion, reference.motion, "{text:?}");
    }
}

#[test]
fn names_with_spaces_and_position_channels_on_any_joint() {
    let text = TWO_JOINTS
        .replace("JOINT Chest", "JOINT Left Upper.Arm:1")
        .replace(
            "CHANNELS 3 Zrotation Xrotation Yrotation",
            "CHANNELS 3 Xrotation Zposition Yrotation",
        );
    let bvh = load_text(&text).unwrap();
    assert_eq!(bvh.skeleton.joints[1].name, "Left Upper.Arm:1");
    assert_eq!(bvh.skeleton.joints[1].rotation_order, None);
    assert!(bvh.skeleton.joints[1].channels[1].is_position());
}

#[test]
fn no_motion_section_and_zero_frames_give_a_skeleton_without_frames() {
    let cut = TWO_JOINTS.find("MOTION").unwrap();
    let bvh = load_text(&TWO_JOINTS[..cut]).unwrap();
    assert_eq!(bvh.motion.frame_count(), 0);
    assert_eq!(bvh.skeleton.joints.len(), 3);

    let head = &TWO_JOINTS[..TWO_JOINTS.find("Frames").unwrap()];
    let zero = load_text(&format!("{head}Frames: 0\nFrame Time: 0.1\n")).unwrap();
    assert_eq!(zero.motion.frame_count(), 0);
    assert!(zero.warnings.is_empty());
}

#[test]
fn errors_point_at_the_offending_token() {
    let cases = [
        (
            TWO_JOINTS.replace("OFFSET 0 10 0", "OFFSET 0 1O 0"),
            "8:12: expected OFFSET's y value (a number), found '1O'",
        ),
        (
            TWO_JOINTS.replace(
                "Zrotation Xrotation Yrotation\n\t\tEnd",
                "Zrotation Xrot Yrotation\n\t\tEnd",
            ),
            "9:24: expected 3 channel names (Xposition … Zrotation), 1 so far, found 'Xrot'",
        ),
        (
            TWO_JOINTS.replace("7 8 9\n-1", "7 8\n-1"),
            "19:16: frame 0 has 8 values, expected 9 (one per channel)",
        ),
        (
            TWO_JOINTS.replace("7 8 9\n-1", "7 8 9 10\n-1"),
            "19:19: frame 0 has more than the 9 values the channels need",
        ),
        (
            TWO_JOINTS.replace("-7 -8", "-7 nan"),
            "20:22: expected a finite number, found 'nan'",
        ),
        (
            TWO_JOINTS.replace("-7 -8", "-7 1e39"),
            "20:22: expected a finite number, found '1e39'",
        ),
        (
            TWO_JOINTS.replace("Frames: 2", "Frames: -2"),
            "17:9: expected the number of frames, found '-2'",
        ),
        (
            TWO_JOINTS.replace("Frame Time: .5", "Frame Time: .5 x"),
            "18:16: expected end of line after the frame time, found 'x'",
        ),
        (
            TWO_JOINTS.replace("\t\t}\n\t}\n}", "\t\t}\n\t}\n}\n}"),
            "16:1: expected ROOT or MOTION, found '}'",
        ),
        (
            TWO_JOINTS.replace(
                "\t\t\tOFFSET 0 5 0\n",
                "\t\t\tOFFSET 0 5 0\n\t\t\tCHANNELS 1 Xrotation\n",
            ),
            "13:4: expected OFFSET or '}' in End Site, found 'CHANNELS'",
        ),
        (
            TWO_JOINTS.replace("\tOFFSET 0 10 0\n", ""),
            "13:2: expected OFFSET in 'Chest', found '}'",
        ),
        (
            TWO_JOINTS.replace("JOINT Chest", "JOINT"),
            "6:7: expected a joint name after JOINT, found end of line",
        ),
        (
            "HIERARCHY\n".to_string(),
            "2:1: expected ROOT, found end of file",
        ),
        (
            TWO_JOINTS.replace("HIERARCHY", "HIERARCHIE"),
            "1:1: expected HIERARCHY, found 'HIERARCHIE'",
        ),
        // A multi-byte character counts as one column.
        (
            TWO_JOINTS.replace("JOINT Chest\n\t{", "JOINT Brüst }"),
            "6:14: expected '{' after 'Brüst', found '}'",
        ),
    ];
    for (text, message) in cases {
        assert_eq!(error_text(&text), format!("t.bvh:{message}"), "{text:?}");
    }
}

#[test]
fn a_file_that_ends_early_names_the_frames_line() {
    let text = TWO_JOINTS.replace("Frames: 2", "Frames: 999999999999");
    assert_eq!(
        error_text(&text),
        "t.bvh:21:1: expected 999999999999 frames as Frames: says (line 17), found 2: the file ends"
    );
}

#[test]
fn nesting_deeper_than_the_limit_is_an_error() {
    let depth = bvhview::limits::MAX_DEPTH + 1;
    let mut text = String::from("HIERARCHY\n");
    for i in 0..depth {
        text.push_str(&format!("JOINT j{i}\n{{\nOFFSET 0 1 0\n"));
    }
    let message = error_text(&text);
    assert!(
        message.ends_with("joints nest deeper than 1000 levels"),
        "{message}"
    );
}

/// Found by fuzzing: a file that ends right after the frame time, without a line end or rows.
#[test]
fn a_file_ending_right_after_the_frame_time_is_an_error_not_a_panic() {
    let text = "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 5\nFrame Time: 0.1";
    assert_eq!(
        error_text(text),
        "t.bvh:9:16: expected 5 frames as Frames: says (line 8), found 0: the file ends"
    );
    assert_eq!(
        error_text(&format!("{text}\t")),
        "t.bvh:9:17: expected 5 frames as Frames: says (line 8), found 0: the file ends"
    );
    let zero = text.replace("Frames: 5", "Frames: 0");
    assert_eq!(load_text(&zero).unwrap().motion.frame_count(), 0);
}
