//! One hand-written input per defect of the article's loader (tests/edge/README.md says what the
//! article does with each); these tests pin what bvhview does with it instead. Every input is the
//! control file `article_base_crlf.bvh` (which the article reads) changed in one way only.

use crate::common;
use bvhview::model::pose::{OffsetMode, world_positions};
use bvhview::{Channel, RotationOrder};
use common::*;
use glam::Vec3;

const ROW_0: [f32; 9] = [0.0, 30.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
const ROW_1: [f32; 9] = [5.0, 30.0, -3.0, 10.0, 20.0, 30.0, -40.0, 50.0, 60.0];
const ROOT_CHANNELS: [Channel; 6] = [
    Channel::Xposition,
    Channel::Yposition,
    Channel::Zposition,
    Channel::Zrotation,
    Channel::Xrotation,
    Channel::Yrotation,
];

fn load_edge(name: &str) -> bvhview::bvh::Bvh {
    load_path(&edge(name))
}

fn print_of(name: &str) -> String {
    let out = bvhview(&["print", edge(name).to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The control file: Hips (6 channels, ZXY) → Chest (ZXY) → End Site, two frames.
#[test]
fn the_control_file_loads_with_the_values_its_text_holds() {
    let bvh = load_edge("article_base_crlf.bvh");
    let joints = &bvh.skeleton.joints;
    let names: Vec<&str> = joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["Hips", "Chest", "Site"]);
    assert_eq!(joints[0].channels, ROOT_CHANNELS);
    assert_eq!(joints[1].channels, ROOT_CHANNELS[3..]);
    assert_eq!(joints[1].rotation_order, Some(RotationOrder::Zxy));
    assert_eq!(joints[1].offset, Vec3::new(0.0, 15.0, 0.0));
    assert!(joints[2].end_site);
    assert_eq!(joints[2].offset, Vec3::new(0.0, 20.0, 0.0));
    assert_eq!(bvh.motion.frame_count(), 2);
    assert_eq!(bvh.motion.frame_time, 0.033333);
    assert_eq!(bvh.motion.frame(0), ROW_0);
    assert_eq!(bvh.motion.frame(1), ROW_1);
    assert!(bvh.warnings.is_empty());
    assert_eq!(
        print_of("article_base_crlf.bvh"),
        "Hips : 0.000000,0.000000,0.000000 -3- zxy\n \
         -Chest : 0.000000,15.000000,0.000000 -3- zxy\n \
         - -Site : 0.000000,20.000000,0.000000 -0- \n"
    );
}

/// The article skips exactly two bytes after each row and drops the last byte of each name (it
/// assumes CR LF); the format error it stops with depends on the file. Here: the same model.
#[test]
fn lf_line_endings_load_the_same_as_crlf() {
    let base = load_edge("article_base_crlf.bvh");
    let lf = load_edge("lf_line_endings.bvh");
    assert_eq!(lf.skeleton, base.skeleton);
    assert_eq!(lf.motion, base.motion);
}

/// The article's row loop expects a blank after the last number of a row, then CR LF.
#[test]
fn rows_without_a_trailing_blank_load_the_same() {
    let base = load_edge("article_base_crlf.bvh");
    let bare = load_edge("row_without_trailing_blank.bvh");
    assert_eq!(bare.skeleton, base.skeleton);
    assert_eq!(bare.motion, base.motion);
}

/// The article reads the root OFFSET in steps of 5 bytes, other OFFSETs and MOTION values in
/// steps of at least 8: `0 15 0` and rows of `0` shift every value after them.
#[test]
fn short_numbers_in_offsets_and_rows_load_the_same() {
    let base = load_edge("article_base_crlf.bvh");
    let short = load_edge("short_numbers.bvh");
    assert_eq!(short.skeleton, base.skeleton);
    assert_eq!(short.motion, base.motion);
}

/// The article reads the root's OFFSET in 5-byte steps (one more after a step that lands on a
/// space), which fit only numbers of 4 or 5 characters: it prints this one as `1.25,0,0.5`. Here
/// the three numbers are read whole.
#[test]
fn a_wide_root_offset_is_read_whole() {
    let bvh = load_edge("root_offset_wide.bvh");
    assert_eq!(bvh.skeleton.joints[0].offset, Vec3::new(1.25, 2.5, 3.75));
    assert!(
        print_of("root_offset_wide.bvh").starts_with("Hips : 1.250000,2.500000,3.750000 -3- zxy\n")
    );
    // The position channels replace it in every frame, as in the control file.
    let base = load_edge("article_base_crlf.bvh");
    assert_eq!(bvh.motion, base.motion);
    let frame = bvh.motion.frame(1);
    assert_eq!(
        world_positions(&bvh.skeleton, frame, OffsetMode::Replace),
        world_positions(&base.skeleton, frame, OffsetMode::Replace)
    );
}

/// The article has room for 16 children per joint. Here 17 and 18 children are all kept, in file
/// order, and each reads its own three columns.
#[test]
fn seventeen_and_eighteen_children_are_all_kept() {
    for n in [17usize, 18] {
        let name = format!("children_{n}.bvh");
        let bvh = load_edge(&name);
        let skeleton = &bvh.skeleton;
        assert_eq!(skeleton.joints.len(), 1 + 2 * n, "{name}");
        assert_eq!(skeleton.joints[0].children.len(), n, "{name}");
        assert_eq!(skeleton.channel_count(), 6 + 3 * n, "{name}");
        let frame = bvh.motion.frame(1);
        let positions = world_positions(skeleton, frame, OffsetMode::Replace);
        for (k, &child) in skeleton.joints[0].children.iter().enumerate() {
            let finger = &skeleton.joints[child];
            assert_eq!(finger.name, format!("Finger{:02}", k + 1));
            assert_eq!(finger.first_channel, 6 + 3 * k);
            // Zrotation of finger k is k + 1 degrees at frame 1; the root is at (0, 30, 0).
            assert_eq!(finger.values(frame), [(k + 1) as f32, 0.0, 0.0]);
            let x = k as f32 + 1.0 - (n as f32 + 1.0) / 2.0;
            let angle = ((k + 1) as f32).to_radians();
            let tip = Vec3::new(x - 5.0 * angle.sin(), 40.0 + 5.0 * angle.cos(), 0.0);
            let site = finger.children[0];
            assert!(
                positions[site].abs_diff_eq(tip, 1e-4),
                "{name} Finger{:02}: {} vs {tip}",
                k + 1,
                positions[site]
            );
        }
        let print = print_of(&name);
        assert_eq!(print.lines().count(), 1 + 2 * n, "{name}");
        assert!(print.ends_with(&format!(
            " -Finger{n:02} : {:.6},10.000000,0.000000 -3- zxy\n - -Site : 0.000000,5.000000,0.000000 -0- \n",
            (n as f32 - 1.0) / 2.0
        )));
    }
}

/// The article keeps at most 22 bytes of a name (23 to 25 load cut short, 26 and more break its
/// load). Every command here keeps the whole name; only `print` cuts it, at 23 bytes, to match
/// the reference prints in tests/oracle/print.
#[test]
fn long_names_are_kept_whole_and_cut_only_by_print() {
    for (file, name, printed) in [
        (
            "name_23_bytes.bvh",
            "mixamorig:LeftHandIndex",
            "mixamorig:LeftHandIndex",
        ),
        (
            "name_25_bytes.bvh",
            "mixamorig:LeftHandMiddle1",
            "mixamorig:LeftHandMiddl",
        ),
        (
            "name_26_bytes.bvh",
            "mixamorig:RightHandMiddle1",
            "mixamorig:RightHandMidd",
        ),
    ] {
        let bvh = load_edge(file);
        assert_eq!(bvh.skeleton.joints[1].name, name);
        assert_eq!(bvh.motion, load_edge("article_base_crlf.bvh").motion);
        let print = print_of(file);
        assert_eq!(
            print.lines().nth(1).unwrap(),
            format!(" -{printed} : 0.000000,15.000000,0.000000 -3- zxy")
        );
        let out = bvhview(&["positions", edge(file).to_str().unwrap(), "--frames", "0"]);
        let csv = String::from_utf8(out.stdout).unwrap();
        assert!(csv.contains(&format!("\n0,{name},0,45,0\n")), "{csv}");
    }
}

/// The article reads `Frames` rows whatever the file holds, past the end of its buffer.
#[test]
fn frames_larger_than_the_rows_is_an_error_at_the_end_of_the_file() {
    let path = edge("frames_more_than_rows.bvh");
    let error = bvhview::bvh::load_file(&path, Default::default())
        .err()
        .unwrap();
    assert_eq!(
        error.to_string(),
        format!(
            "{}:22:1: expected 4 frames as Frames: says (line 17), found 3: the file ends",
            path.display()
        )
    );
    assert!(error.is_the_callers(), "exit 2: the input's fault");
    let out = bvhview(&["info", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
}

/// With `Frames: 0` the article's `draw` reads row 0 of an empty array; without MOTION its scan for
/// `F` runs off the buffer. Here both are the skeleton with no frames, drawn in its rest pose.
#[test]
fn frames_zero_and_no_motion_give_the_skeleton_at_rest() {
    let base = load_edge("article_base_crlf.bvh");
    for (file, frame_time) in [("frames_zero.bvh", 0.033333), ("no_motion.bvh", 0.0)] {
        let bvh = load_edge(file);
        assert_eq!(bvh.skeleton, base.skeleton, "{file}");
        assert_eq!(bvh.motion.frame_count(), 0, "{file}");
        assert!(bvh.motion.data.is_empty());
        assert_eq!(bvh.motion.frame_time, frame_time, "{file}");
        let out = bvhview(&["positions", edge(file).to_str().unwrap()]);
        assert!(out.status.success(), "{file}");
        assert_eq!(
            String::from_utf8(out.stdout).unwrap(),
            "frame,joint,x,y,z\n0,Hips,0,0,0\n0,Chest,0,15,0\n0,Chest_End,0,35,0\n",
            "{file}"
        );
    }
}

/// R = Rz(z) · Rx(x) · Ry(y) applied to v, in f64, written out from the rotation matrices.
fn rotate_zxy(z: f64, x: f64, y: f64, v: [f64; 3]) -> [f64; 3] {
    let (sz, cz) = z.to_radians().sin_cos();
    let (sx, cx) = x.to_radians().sin_cos();
    let (sy, cy) = y.to_radians().sin_cos();
    let ry = [cy * v[0] + sy * v[2], v[1], -sy * v[0] + cy * v[2]];
    let rx = [ry[0], cx * ry[1] - sx * ry[2], sx * ry[1] + cx * ry[2]];
    [cz * rx[0] - sz * rx[1], sz * rx[0] + cz * rx[1], rx[2]]
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// The article reads the first three channel names of a non-root joint as its rotation order, so
/// `Xposition Yposition Zposition` becomes XYZ rotations and every column after it shifts. Here
/// the position channels replace the OFFSET (or add to it with `--offset-mode add`).
#[test]
fn position_channels_on_a_non_root_joint_move_it() {
    let bvh = load_edge("position_channels_non_root.bvh");
    let chest = &bvh.skeleton.joints[1];
    assert_eq!(chest.channels, ROOT_CHANNELS);
    assert_eq!(chest.first_channel, 6);
    let frame = bvh.motion.frame(1);
    assert_eq!(chest.values(frame), [1.0, 16.0, -2.0, -40.0, 50.0, 60.0]);
    for (mode, chest_local) in [
        (OffsetMode::Replace, [1.0, 16.0, -2.0]),
        (OffsetMode::Add, [1.0, 31.0, -2.0]),
    ] {
        let root = [5.0, 30.0, -3.0];
        let chest_world = add(root, rotate_zxy(10.0, 20.0, 30.0, chest_local));
        let site_in_chest = rotate_zxy(-40.0, 50.0, 60.0, [0.0, 20.0, 0.0]);
        let site_world = add(chest_world, rotate_zxy(10.0, 20.0, 30.0, site_in_chest));
        let got = world_positions(&bvh.skeleton, frame, mode);
        for (index, want) in [(0, root), (1, chest_world), (2, site_world)] {
            let want = Vec3::new(want[0] as f32, want[1] as f32, want[2] as f32);
            assert!(
                got[index].abs_diff_eq(want, 1e-4),
                "{mode:?} joint {index}: {} vs {want}",
                got[index]
            );
        }
    }
}

/// A root written `JOINT` and End Sites written `JOINT Site` with `CHANNELS 0`: the article's
/// `processChannels` steps 30 bytes past `CHANNELS 0`, over the braces that follow, and its load
/// stops with a format error. Here the Sites are End Sites and take no columns.
#[test]
fn joint_site_with_channels_0_is_an_end_site_and_takes_no_columns() {
    let bvh = load_edge("joint_site_channels_0.bvh");
    let joints = &bvh.skeleton.joints;
    let names: Vec<&str> = joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["Hips", "Chest", "Site", "Tail", "Site"]);
    assert_eq!(joints[0].parent, None);
    assert!(joints[2].end_site && joints[2].channels.is_empty());
    assert!(joints[4].end_site && joints[4].channels.is_empty());
    assert_eq!(bvh.skeleton.channel_count(), 12);
    assert_eq!(joints[3].first_channel, 9);
    assert_eq!(joints[3].values(bvh.motion.frame(1)), [70.0, 0.0, 0.0]);
}

/// A root written `JOINT` (the control file otherwise). The article never checks the
/// root's keyword; its fixed 7-byte skip for `\r\nROOT ` stops on the blank before the name, so
/// it names the root `" Hips"` and loads the rest as the control file. Here it is the root,
/// named as written, with the control file's model.
#[test]
fn a_root_written_joint_is_read_as_the_root_it_is() {
    let control = load_edge("article_base_crlf.bvh");
    let bvh = load_edge("root_written_joint.bvh");
    assert_eq!(bvh.skeleton, control.skeleton);
    assert_eq!(bvh.motion, control.motion);
    assert_eq!(bvh.skeleton.joints[0].name, "Hips");
    assert_eq!(bvh.skeleton.joints[0].parent, None);
}

/// Two blanks between Chest's rotation channel names. The article reads its letters 10
/// and 20 bytes on and lands on blanks, and its 30-byte step on the `n` of `Yrotation` (a format
/// error). Here the names are words: the control file's model.
#[test]
fn blanks_between_channel_names_do_not_matter() {
    let control = load_edge("article_base_crlf.bvh");
    let bvh = load_edge("channel_names_two_blanks.bvh");
    assert_eq!(bvh.skeleton, control.skeleton);
    assert_eq!(bvh.motion, control.motion);
}

/// A root with three rotation channels and rows of six numbers. The article counts
/// `jointCount * 3 + 3` = 9 numbers a row, as if every root had three positions, and reads past
/// its buffer. Here a row is as wide as the channels: the root stays at its OFFSET and turns.
#[test]
fn a_root_with_rotations_only_reads_rows_of_its_own_width() {
    let bvh = load_edge("root_rotations_only.bvh");
    assert_eq!(bvh.skeleton.channel_count(), 6);
    assert_eq!(bvh.motion.frame_count(), 2);
    assert_eq!(bvh.motion.frame(1), [10.0, 20.0, 30.0, -40.0, 50.0, 60.0]);
    let root = &bvh.skeleton.joints[0];
    assert!(root.channels.iter().all(|c| c.is_rotation()));
    let world = world_positions(&bvh.skeleton, bvh.motion.frame(1), OffsetMode::Replace);
    assert_eq!(world[0], Vec3::ZERO);
}

/// `JOINT Chest ` with a blank before the line end. The article keeps the blank in the
/// name (`"Chest "`); here a name is a word, and the file is the control file.
#[test]
fn a_joint_name_ends_at_its_last_letter() {
    let control = load_edge("article_base_crlf.bvh");
    let bvh = load_edge("joint_name_trailing_blank.bvh");
    assert_eq!(bvh.skeleton.joints[1].name, "Chest");
    assert_eq!(bvh.skeleton, control.skeleton);
}

/// A bare `JOINT`. The article's `newNode` copies nothing and writes `name[-1]`, and the
/// file loads with an empty name; here it is refused where the name should be.
#[test]
fn a_joint_without_a_name_is_refused_where_the_name_should_be() {
    let path = edge("joint_without_name.bvh");
    let error = bvhview::bvh::loader::load_file(&path, Default::default()).unwrap_err();
    let text = error.to_string();
    assert!(
        text.ends_with(
            "joint_without_name.bvh:6:7: expected a joint name after JOINT, found end of line"
        ),
        "{text}"
    );
    assert!(error.is_the_callers(), "exit 2: the input's fault");
    // What the article does instead, with its reason (UBSan: index -1 in newNode).
    let path = edge("joint_without_name.bvh");
    let first = |lang: &str| {
        let out = bvhview(&["trace", path.to_str().unwrap(), "--explain", "--lang", lang]);
        String::from_utf8(out.stdout).unwrap()
    };
    assert_eq!(
        first("en"),
        "// what the article's program does with this file: misreads it: a joint on line 6 has \
         no name: newNode copies no byte and writes its terminator at name[-1] \
         (UndefinedBehaviorSanitizer: index -1 out of bounds), and keeps the joint with an empty \
         name\n"
    );
    assert_eq!(
        first("zh"),
        "// 原文的程式對這個檔案：讀錯：第 6 行的關節沒有名字：newNode 一個位元組也沒複製，把結尾的 \
         0 寫到 name[-1]（UndefinedBehaviorSanitizer：索引 -1 超出範圍），這個關節就以空的名字留下\n"
    );
}

/// A chain deeper than GL's modelview stack. The article's loader reads it whole, but
/// its draw pushes one matrix per joint: at `Chain31` (the 32nd push) the push is ignored, and
/// `Branch`, drawn after the chain returns, gets an ancestor's matrix. `--explain` says so in
/// both languages; here every joint stands where forward kinematics puts it.
#[test]
fn a_chain_deeper_than_the_gl_stack_misdraws_the_branch_after_it() {
    let path = edge("chain_36_deep.bvh");
    let text = path.to_str().unwrap();
    let first_line = |lang: &str| {
        let out = bvhview(&["trace", text, "--explain", "--lang", lang]);
        assert!(out.status.success());
        String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .next()
            .unwrap()
            .to_string()
    };
    assert_eq!(
        first_line("en"),
        "// what the article's program does with this file: misreads it: its draw pushes one \
         matrix per joint and GL's stack holds 32: at 'Chain31' glPushMatrix overflows and is \
         ignored, the pops after it take the matrices of joints above, and 'Branch' is drawn \
         from a matrix that is not its own: in frame 0 at (10, 0, 0), where the file puts it at \
         (10, 30, 0)"
    );
    assert_eq!(
        first_line("zh"),
        "// 原文的程式對這個檔案：讀錯：它的 draw 每個關節推入一個矩陣，GL 的矩陣堆疊只有 32 層：\
         到了 'Chain31'，glPushMatrix 溢位而被忽略，之後的彈出拿走了上層關節的矩陣，'Branch' \
         用的不是自己的矩陣：第 0 個影格畫在 (10, 0, 0)，檔案要它在 (10, 30, 0)"
    );
    // What glGetError says (measured with bench/glut/run.sh: 7 overflows, 7 underflows).
    let out = bvhview(&["trace", text, "--explain"]);
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        stdout.lines().nth(1).unwrap(),
        "// GL's modelview stack holds 32 matrices, and the article's draw would hold 39 at once \
         (the view, and one per joint and End Site down its deepest path): glGetError says \
         GL_STACK_OVERFLOW after each of 7 pushes, from 'Chain31' on, and GL_STACK_UNDERFLOW \
         after each of 7 pops"
    );
    let bvh = load_edge("chain_36_deep.bvh");
    let world = world_positions(&bvh.skeleton, bvh.motion.frame(0), OffsetMode::Replace);
    let branch = bvh
        .skeleton
        .joints
        .iter()
        .position(|j| j.name == "Branch")
        .unwrap();
    assert_eq!(world[branch], Vec3::new(10.0, 30.0, 0.0));
}

/// A chain of `joints` joints under the root (the root included: `joints` in all), then an End
/// Site, laid out as the article reads it (CR LF, numbers of 8 characters), rows of zeros but
/// frame 1's y = 30.
fn chain(joints: usize) -> String {
    let mut text = String::from(
        "HIERARCHY\r\nROOT Hips\r\n{\r\n\tOFFSET 0.00 0.00 0.00\r\n\tCHANNELS 6 Xposition \
         Yposition Zposition Zrotation Xrotation Yrotation\r\n",
    );
    for i in 1..joints {
        let tabs = "\t".repeat(i);
        text += &format!(
            "{tabs}JOINT Chain{i:02}\r\n{tabs}{{\r\n{tabs}\tOFFSET 0.000000 2.000000 0.000000\r\n\
             {tabs}\tCHANNELS 3 Zrotation Xrotation Yrotation\r\n"
        );
    }
    let tabs = "\t".repeat(joints);
    text += &format!(
        "{tabs}End Site\r\n{tabs}{{\r\n{tabs}\tOFFSET 0.000000 2.000000 0.000000\r\n{tabs}}}\r\n"
    );
    for i in (0..joints).rev() {
        text += &format!("{}}}\r\n", "\t".repeat(i));
    }
    let width = joints * 3 + 3;
    let zeros = |n: usize| "0.000000 ".repeat(n);
    text += &format!(
        "MOTION\r\nFrames: 2\r\nFrame Time: 0.033333\r\n{}\r\n0.000000 30.000000 {}\r\n",
        zeros(width),
        zeros(width - 2)
    );
    text
}

/// bvhview's depth limit counts every level of the tree, End Sites included: 1,000. A chain of
/// 999 joints (the root included) and its End Site is 1,000 deep and loads; one of 1,000 joints
/// and its End Site is refused. The article's program reads the 1,001-deep file as written (its
/// draw overflows GL's stack, but a chain alone draws every sphere on the way down: measured,
/// 0 pixels differ), and `--explain` says so, with what glGetError says.
#[test]
fn the_depth_limit_is_1000_levels_end_sites_included() {
    let dir = tempfile::tempdir().unwrap();
    let deepest = dir.path().join("chain_999.bvh");
    std::fs::write(&deepest, chain(999)).unwrap();
    let bvh = load_path(&deepest);
    assert_eq!(bvh.skeleton.joints.len(), 1000);
    let refused = dir.path().join("chain_1000.bvh");
    std::fs::write(&refused, chain(1000)).unwrap();
    let out = bvhview(&["trace", refused.to_str().unwrap(), "--explain"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        format!(
            "bvhview: {}:4002:1001: joints nest deeper than 1000 levels\n",
            refused.display()
        )
    );
    assert_eq!(
        String::from_utf8(out.stdout).unwrap(),
        "// what the article's program does with this file: reads it as written: print and the \
         draw of every frame are what the file says (joints, names, OFFSETs, translations, \
         rotations)\n\
         // GL's modelview stack holds 32 matrices, and the article's draw would hold 1002 at \
         once (the view, and one per joint and End Site down its deepest path): glGetError says \
         GL_STACK_OVERFLOW after each of 970 pushes, from 'Chain31' on, and GL_STACK_UNDERFLOW \
         after each of 970 pops\n"
    );
}

/// A chain of 40 joints under the root: the article's draw overflows GL's stack and reads the
/// file as written all the same; `--explain` says the errors glGetError reports (measured with
/// bench/glut/run.sh: 11 of each), in both languages.
#[test]
fn a_chain_40_deep_is_read_as_written_with_gl_stack_errors_said() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("chain_40.bvh");
    std::fs::write(&path, chain(41)).unwrap();
    let lines = |lang: &str| {
        let out = bvhview(&["trace", path.to_str().unwrap(), "--explain", "--lang", lang]);
        assert!(out.status.success());
        let text = String::from_utf8(out.stdout).unwrap();
        text.lines().take(2).map(str::to_string).collect::<Vec<_>>()
    };
    assert_eq!(
        lines("en"),
        [
            "// what the article's program does with this file: reads it as written: print and \
             the draw of every frame are what the file says (joints, names, OFFSETs, \
             translations, rotations)",
            "// GL's modelview stack holds 32 matrices, and the article's draw would hold 43 at \
             once (the view, and one per joint and End Site down its deepest path): glGetError \
             says GL_STACK_OVERFLOW after each of 11 pushes, from 'Chain31' on, and \
             GL_STACK_UNDERFLOW after each of 11 pops",
        ]
    );
    assert_eq!(
        lines("zh"),
        [
            "// 原文的程式對這個檔案：如實讀入：print 與每個影格的 draw 都和檔案所寫的相同（關節、\
             名字、OFFSET、平移與旋轉）",
            "// GL 的模型檢視矩陣堆疊只有 32 層，原文的 draw 同時要放 43 個矩陣（檢視矩陣，加上最深\
             一條路徑上每個關節與 End Site 各一個）：glGetError 在 11 次推入後都回報 \
             GL_STACK_OVERFLOW（從 'Chain31' 的推入起），在 11 次彈出後都回報 GL_STACK_UNDERFLOW",
        ]
    );
}

/// A blank line between two MOTION rows: the article's row loop reads it right (`atof` skips
/// the line end before the next number: `print` and both frames' draw calls are the control
/// file's, measured, ASan and UBSan silent), and so does bvhview.
#[test]
fn a_blank_line_between_rows_is_read_as_no_row() {
    let base = load_edge("article_base_crlf.bvh");
    let blank = load_edge("blank_line_between_rows.bvh");
    assert_eq!(blank.skeleton, base.skeleton);
    assert_eq!(blank.motion, base.motion);
    assert!(blank.warnings.is_empty());
    assert_eq!(
        print_of("blank_line_between_rows.bvh"),
        print_of("article_base_crlf.bvh")
    );
}

/// An empty file: `new unsigned char[0]`, and the check of the header reads the byte after it
/// (valgrind reports it, ASan does not), which is not `H`: `loadFile` returns 0, and the crash is
/// `init`'s print of the null root (SIGSEGV in `printRecursive`; measured).
#[test]
fn explain_on_an_empty_file_says_the_header_check_finds_no_h() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty.bvh");
    std::fs::write(&path, b"").unwrap();
    let out = bvhview(&["trace", path.to_str().unwrap(), "--explain"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8(out.stdout).unwrap(),
        "// what the article's program does with this file: rejects it: the file is empty: new \
         unsigned char[0] gives a buffer of no bytes, and the check of the header compares the \
         byte after it with the H of HIERARCHY (valgrind reports that read, AddressSanitizer \
         does not); it is not H; loadFile returns 0 (init then prints the null root anyway, \
         which crashes)\n"
    );
}

/// A row of 6 values where the article reads 9: the note names the article's column as one of
/// its own rows, past the end of the file's.
#[test]
fn explain_notes_a_column_past_the_files_rows() {
    let path = edge("root_rotations_only.bvh");
    let out = bvhview(&["trace", path.to_str().unwrap(), "--explain"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains(
            "// Zrotation: column [3]; the article's pFrame[0] is [6] of its rows of 9 values \
             (jointCount * 3 + 3), past the end of the file's rows of 6\n"
        ),
        "{text}"
    );
    assert!(!text.contains("column [6]"), "{text}");
}

// Five more defects of the article's loader, each with its input in tests/edge, and
// the smaller ones the chapter gives a sentence each.

/// A skeleton of the root alone (Hips and its End Site, six columns): the article's `loadFile`
/// returns false when `jointCount == 1`, after its `clear()` has deleted row pointers it never
/// set. Here it loads like any other file, and `trace --explain` says the article crashes on it.
#[test]
fn a_skeleton_of_the_root_alone_loads() {
    let bvh = load_edge("root_only.bvh");
    let joints = &bvh.skeleton.joints;
    let names: Vec<&str> = joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["Hips", "Site"]);
    assert_eq!(joints[0].channels, ROOT_CHANNELS);
    assert!(joints[1].end_site);
    assert_eq!(bvh.skeleton.channel_count(), 6);
    assert_eq!(bvh.motion.frame_count(), 2);
    assert_eq!(bvh.motion.frame(1), &ROW_1[..6]);
    assert_eq!(
        print_of("root_only.bvh"),
        "Hips : 0.000000,0.000000,0.000000 -3- zxy\n -Site : 0.000000,20.000000,0.000000 -0- \n"
    );
    // The End Site: (0, 20, 0) turned by Rz(10) · Rx(20) · Ry(30), then moved to (5, 30, -3).
    let want = add(
        [5.0, 30.0, -3.0],
        rotate_zxy(10.0, 20.0, 30.0, [0.0, 20.0, 0.0]),
    );
    let site = world_positions(&bvh.skeleton, bvh.motion.frame(1), OffsetMode::Replace)[1];
    let want = Vec3::new(want[0] as f32, want[1] as f32, want[2] as f32);
    assert!(site.abs_diff_eq(want, 1e-4), "{site} vs {want}");
    let file = edge("root_only.bvh");
    let out = bvhview(&["positions", file.to_str().unwrap(), "--frames", "1"]);
    assert!(out.status.success());
    assert_eq!(
        String::from_utf8(out.stdout).unwrap(),
        "frame,joint,x,y,z\n1,Hips,5,30,-3\n1,Hips_End,1.7364817,48.50833,3.8404026\n"
    );
    // The article's program: clear() deletes the two row pointers it never set.
    assert_eq!(
        verdict_of(&file),
        "// what the article's program does with this file: crashes on it: a skeleton of one \
         joint (jointCount == 1): loadFile calls clear(), which deletes 2 row pointers it never set"
    );
}

/// `Yrotation Yrotation Xrotation` on the root: the article's `getFlags` sums to 2 + 4 + 4 − 10
/// = 0, the flags of an End Site, so `roateSpace` turns Hips by nothing and leaves `pFrame` where
/// it is: Chest then reads Hips's three rotation columns. Here Hips turns as written (about Y,
/// Y, then X) and Chest reads its own columns.
#[test]
fn rotation_letters_whose_flags_sum_to_0_turn_as_written() {
    let bvh = load_edge("rotation_flags_0.bvh");
    let joints = &bvh.skeleton.joints;
    assert_eq!(
        joints[0].channels,
        [
            Channel::Xposition,
            Channel::Yposition,
            Channel::Zposition,
            Channel::Yrotation,
            Channel::Yrotation,
            Channel::Xrotation,
        ]
    );
    assert_eq!(joints[0].rotation_order, None);
    assert_eq!(joints[1].first_channel, 6);
    assert_eq!(joints[1].values(bvh.motion.frame(1)), [-40.0, 50.0, 60.0]);
    // The same print as the article's: no order for Hips.
    assert_eq!(
        print_of("rotation_flags_0.bvh"),
        "Hips : 0.000000,0.000000,0.000000 -0- \n \
         -Chest : 0.000000,15.000000,0.000000 -3- zxy\n \
         - -Site : 0.000000,20.000000,0.000000 -0- \n"
    );
    let out = bvhview(&[
        "trace",
        edge("rotation_flags_0.bvh").to_str().unwrap(),
        "--frame",
        "1",
    ]);
    let trace = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = trace.lines().collect();
    // Between the camera (4 lines) and the floor (6 lines): the skeleton's calls.
    assert_eq!(
        lines[4..lines.len() - 6],
        [
            "glPushMatrix();",
            "glTranslatef(5.000000, 30.000000, -3.000000);",
            "glRotatef(10.000000, 0.000000, 1.000000, 0.000000);",
            "glRotatef(20.000000, 0.000000, 1.000000, 0.000000);",
            "glRotatef(30.000000, 1.000000, 0.000000, 0.000000);",
            "glutSolidSphere(1.000000, 20, 16);",
            "glPushMatrix();",
            "glTranslatef(0.000000, 15.000000, 0.000000);",
            "glRotatef(-40.000000, 0.000000, 0.000000, 1.000000);",
            "glRotatef(50.000000, 1.000000, 0.000000, 0.000000);",
            "glRotatef(60.000000, 0.000000, 1.000000, 0.000000);",
            "glutSolidSphere(1.000000, 20, 16);",
            "glPushMatrix();",
            "glTranslatef(0.000000, 20.000000, 0.000000);",
            "glutSolidSphere(1.000000, 20, 16);",
            "glPopMatrix();",
            "glPopMatrix();",
            "glPopMatrix();",
        ]
    );
}

/// `tests/oracle/inputs/tiny_crlf.bvh` with each `{` written at the end of its JOINT line: the
/// article's `newNode` takes the brace into the name (`Chest {`), its brace counter reaches 0
/// early, and `loadFile` returns true with 4 of the 12 joints and End Sites (then 0 frames, from
/// an `F` inside an OFFSET). Here it is the same model as tiny_crlf.bvh.
#[test]
fn a_brace_on_the_joint_line_reads_as_on_its_own_line() {
    let tiny = load_path(&oracle("inputs/tiny_crlf.bvh"));
    let braces = load_edge("brace_on_joint_line.bvh");
    assert_eq!(braces.skeleton, tiny.skeleton);
    assert_eq!(braces.motion, tiny.motion);
    assert_eq!(braces.skeleton.joints.len(), 12);
    assert!(braces.skeleton.joints.iter().all(|j| !j.name.contains('{')));
    assert_eq!(
        print_of("brace_on_joint_line.bvh"),
        std::fs::read_to_string(oracle("print/tiny_crlf.txt")).unwrap()
    );
}

/// `Frames: -1` and `Frames: 4294967295` (what the article's `(unsigned)atoi` makes of -1): the
/// article allocates 4294967295 row pointers, 32 GiB, before it reads a row, and dies of
/// `bad_alloc`. Here -1 is not a frame count, and a count past the rows is an error at the end of
/// the file; neither allocates by the count (an allocation of 4294967295 rows of 9 floats would
/// abort this test).
#[test]
fn frames_minus_one_or_huge_is_an_error_not_an_allocation() {
    for (file, message) in [
        (
            "frames_minus_one.bvh",
            ":17:9: expected the number of frames, found '-1'",
        ),
        (
            "frames_huge.bvh",
            ":21:1: expected 4294967295 frames as Frames: says (line 17), found 2: the file ends",
        ),
    ] {
        let path = edge(file);
        let error = bvhview::bvh::load_file(&path, Default::default())
            .err()
            .unwrap();
        assert_eq!(error.to_string(), format!("{}{message}", path.display()));
        assert!(error.is_the_callers(), "exit 2: the input's fault");
        let out = bvhview(&["info", path.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{file}");
        assert!(out.stdout.is_empty(), "{file}");
        assert_eq!(
            String::from_utf8(out.stderr).unwrap(),
            format!("bvhview: {}{message}\n", path.display())
        );
    }
}

/// A UTF-8 byte-order mark, or a blank line, before HIERARCHY: the article compares the first
/// nine bytes with "HIERARCHY", returns false, and its `init` prints the null root. Here both
/// load as the control file does.
#[test]
fn a_byte_order_mark_or_a_blank_line_before_hierarchy_loads_the_same() {
    let base = load_edge("article_base_crlf.bvh");
    for file in ["bom.bvh", "blank_line_before_hierarchy.bvh"] {
        let bytes = std::fs::read(edge(file)).unwrap();
        assert!(bytes.starts_with(b"\xEF\xBB\xBFHIERARCHY") || bytes.starts_with(b"\r\nHIERARCHY"));
        let bvh = load_edge(file);
        assert_eq!(bvh.skeleton, base.skeleton, "{file}");
        assert_eq!(bvh.motion, base.motion, "{file}");
        assert_eq!(print_of(file), print_of("article_base_crlf.bvh"), "{file}");
    }
}

/// The article steps 8 bytes from the `F` of `Frames:` and 12 from that of `Frame Time:` before
/// `atoi`/`atof`, which skip blanks: it needs at least one blank after each colon (`Frames:12`
/// reads 2, `Frames:2` reads 0). Here the labels are words, with any blanks around the colon,
/// but a blank after it: `Frames:2` is refused.
#[test]
fn frames_and_frame_time_are_words_with_any_blanks() {
    let control = std::fs::read_to_string(edge("article_base_crlf.bvh")).unwrap();
    let base = load_edge("article_base_crlf.bvh");
    for (from, to) in [
        ("Frames: 2", "Frames :\t2"),
        ("Frames: 2", "Frames:    2"),
        ("Frame Time: 0.033333", "Frame Time:\t\t0.033333"),
        ("Frame Time: 0.033333", "Frame Time : 0.033333"),
    ] {
        let bvh = load_text(&control.replace(from, to)).unwrap();
        assert_eq!(bvh.motion, base.motion, "{to}");
    }
    assert_eq!(
        error_text(&control.replace("Frames: 2", "Frames:2")),
        "t.bvh:17:1: expected 'Frames:', found 'Frames:2'"
    );
}

/// The article's buffer holds no 0 byte after the file, yet its loop looks for one to find the
/// end: on the control file cut after `End Site` (`head -n 10`) it reads past the buffer. Here
/// the end of the file is where its bytes end.
#[test]
fn a_file_cut_in_the_hierarchy_ends_at_its_last_byte() {
    let control = std::fs::read_to_string(edge("article_base_crlf.bvh")).unwrap();
    let cut: String = control.split_inclusive('\n').take(10).collect();
    assert!(cut.ends_with("\t\tEnd Site\r\n"));
    assert_eq!(
        error_text(&cut),
        "t.bvh:11:1: expected '{' after 'Site', found end of file"
    );
}

/// The article's `reshape` divides the width by the height; bvhview's pictures are at least one
/// pixel high (its window skips a resize to zero, and `reshape` divides by at least 1).
#[test]
fn a_picture_zero_pixels_high_is_refused() {
    let out = bvhview(&[
        "snapshot",
        edge("article_base_crlf.bvh").to_str().unwrap(),
        "--size",
        "600x0",
        "-o",
        std::env::temp_dir()
            .join("bvhview-zero-high.png")
            .to_str()
            .unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8(out.stderr)
            .unwrap()
            .contains("--size 600x0: width and height must be 1 to 16384")
    );
}

/// The article returns early from `loadFile` without `fclose` on every failed load. Here a
/// failed load closes its file: 200 failures leave the process's open files as they were (give
/// or take what the tests running beside this one open).
#[cfg(target_os = "linux")]
#[test]
fn a_failed_load_closes_its_file() {
    let open = || std::fs::read_dir("/proc/self/fd").unwrap().count();
    let path = edge("frames_minus_one.bvh");
    let before = open();
    for _ in 0..200 {
        assert!(bvhview::bvh::load_file(&path, Default::default()).is_err());
    }
    let after = open();
    assert!(
        after < before + 50,
        "{before} open files before, {after} after"
    );
}

// Four more defects of the article's program, each with an input (two of them made
// here, gigabytes long but sparse) and what bvhview does instead. tests/edge/README.md records what
// the rebuilt program does with each; `bvh::article` repeats it, and `trace --explain` says it.

/// The first line of `trace FILE --explain`: what the article's program does with the file.
fn verdict_of(path: &std::path::Path) -> String {
    let out = bvhview(&["trace", path.to_str().unwrap(), "--explain"]);
    let stdout = String::from_utf8(out.stdout).unwrap();
    stdout.lines().next().unwrap_or_default().to_string()
}

/// A second ROOT after the first: the article's hierarchy loop ends when the first root's braces
/// balance, its scans for `Frames` and `Frame Time` stop inside `Prop`'s OFFSET lines (0 frames),
/// and its `draw` reads row 0 of an empty array. Here both trees load, each reading its own
/// columns.
#[test]
fn two_roots_are_two_trees() {
    let bvh = load_edge("two_roots.bvh");
    let skeleton = &bvh.skeleton;
    assert_eq!(skeleton.roots().count(), 2);
    let prop = skeleton
        .joints
        .iter()
        .position(|j| j.name == "Prop")
        .unwrap();
    assert_eq!(skeleton.joints[prop].parent, None);
    assert_eq!(skeleton.joints[prop].first_channel, 9);
    assert_eq!(skeleton.channel_count(), 15);
    assert_eq!(bvh.motion.frame_count(), 2);
    assert_eq!(
        print_of("two_roots.bvh"),
        "Hips : 0.000000,0.000000,0.000000 -3- zxy\n \
         -Chest : 0.000000,15.000000,0.000000 -3- zxy\n \
         - -Site : 0.000000,20.000000,0.000000 -0- \n\
         Prop : 50.000000,0.000000,0.000000 -3- zxy\n \
         -Site : 0.000000,10.000000,0.000000 -0- \n"
    );
    // Frame 1: Prop at (50, 0, 10), turned 90° about X, so its End Site's (0, 10, 0) points
    // along +Z; the first tree is the control's.
    let out = bvhview(&[
        "positions",
        edge("two_roots.bvh").to_str().unwrap(),
        "--frames",
        "1",
    ]);
    let csv = String::from_utf8(out.stdout).unwrap();
    assert!(
        csv.contains("\n1,Prop,50,0,10\n1,Prop_End,50,0,20\n"),
        "{csv}"
    );
    let control = world_positions(
        &load_edge("article_base_crlf.bvh").skeleton,
        &ROW_1,
        OffsetMode::Replace,
    );
    let both = world_positions(skeleton, bvh.motion.frame(1), OffsetMode::Replace);
    assert_eq!(both[..3], control[..]);
    assert!(
        verdict_of(&edge("two_roots.bvh")).ends_with(
            "crashes on it: loadFile returns 1 with frameCount 0, and draw reads row 0 of an empty array"
        )
    );
}

/// `Zposition Xposition Yposition` on the root: the article copies columns 0, 1 and 2 into the
/// root's x, y and z whatever their names, so frame 1 (`5 30 -3`) is drawn at (5, 30, -3). Here
/// each position channel sets its own axis: (30, -3, 5).
#[test]
fn root_position_channels_are_read_in_their_order() {
    let bvh = load_edge("root_positions_zxy.bvh");
    assert_eq!(
        bvh.skeleton.joints[0].channels[..3],
        [Channel::Zposition, Channel::Xposition, Channel::Yposition]
    );
    let positions = world_positions(&bvh.skeleton, bvh.motion.frame(1), OffsetMode::Replace);
    assert_eq!(positions[0], Vec3::new(30.0, -3.0, 5.0));
    let file = edge("root_positions_zxy.bvh");
    let out = bvhview(&["trace", file.to_str().unwrap(), "--frame", "1", "--explain"]);
    let trace = String::from_utf8(out.stdout).unwrap();
    assert!(trace.contains(
        "glTranslatef(30.000000, -3.000000, 5.000000);    // OFFSET (0, 0, 0), replaced by Zposition = [0], Xposition = [1], Yposition = [2]; the article translates by columns [0], [1], [2] as x, y, z: (5, 30, -3)"
    ), "{trace}");
    assert!(verdict_of(&file).ends_with(
        "misreads it: in frame 0 it translates 'Hips' by (0, 30, 0) where the file means (30, 0, 0)"
    ));
}

/// The root's rotations before its positions: the article's scan for the first `r` finds them,
/// but its `p += 30` then lands on `Xposition` (`_X_ _88_ file format error!!`). Here the channels
/// are read as written: the rows, reordered to match, give the control file's pose.
#[test]
fn a_root_with_its_rotations_first_means_the_same() {
    let base = load_edge("article_base_crlf.bvh");
    let first = load_edge("root_rotations_first.bvh");
    assert_eq!(first.skeleton.joints[0].channels[..3], ROOT_CHANNELS[3..]);
    for frame in 0..2 {
        assert_eq!(
            world_positions(
                &first.skeleton,
                first.motion.frame(frame),
                OffsetMode::Replace
            ),
            world_positions(
                &base.skeleton,
                base.motion.frame(frame),
                OffsetMode::Replace
            ),
            "frame {frame}"
        );
    }
    assert!(
        verdict_of(&edge("root_rotations_first.bvh"))
            .contains("rejects it: at line 5, column 43 its dispatcher meets a byte it has no case for and prints _X_ _88_ file format error!!")
    );
}

/// `atof` reads the `-1.` of MSVC's NaN text `-1.#IND00` and nothing of `nonsense!`: the article
/// loads them as -1 and 0. Here a word that is not a finite number is an error at its place.
#[test]
fn words_that_are_not_numbers_are_errors() {
    let path = edge("motion_not_numbers.bvh");
    let error = bvhview::bvh::load_file(&path, Default::default())
        .err()
        .unwrap();
    assert_eq!(
        error.to_string(),
        format!(
            "{}:20:30: expected a finite number, found '-1.#IND00'",
            path.display()
        )
    );
    assert!(error.is_the_callers(), "exit 2: the input's fault");
    let dir = tempfile::tempdir().unwrap();
    let only = dir.path().join("nonsense.bvh");
    let text = std::fs::read(&path).unwrap();
    let text = String::from_utf8(text)
        .unwrap()
        .replace("-1.#IND00", "10.000000");
    std::fs::write(&only, text).unwrap();
    let error = bvhview::bvh::load_file(&only, Default::default())
        .err()
        .unwrap();
    assert!(
        error
            .to_string()
            .ends_with(":20:71: expected a finite number, found 'nonsense!'"),
        "{error}"
    );
    assert_eq!(
        verdict_of(&path),
        "// what the article's program does with this file: misreads it: atof reads words that are \
         not numbers, without a word: '-1.#IND00' (line 20, column 30) as -1, 'nonsense!' (line 20, \
         column 71) as 0"
    );
}

/// The control file followed by a hole (zeros the file system does not store), `length` bytes in
/// all; `None` where the file system stores the zeros (then the test would write gigabytes).
#[cfg(target_os = "linux")]
fn sparse_control(dir: &std::path::Path, length: u64) -> Option<std::path::PathBuf> {
    use std::os::unix::fs::MetadataExt;
    let path = dir.join(format!("control_then_zeros_{length}.bvh"));
    std::fs::copy(edge("article_base_crlf.bvh"), &path).unwrap();
    let file = std::fs::OpenOptions::new().write(true).open(&path).unwrap();
    file.set_len(length).unwrap();
    let stored = file.metadata().unwrap().blocks() * 512;
    if stored > 1 << 20 {
        drop(file);
        std::fs::remove_file(&path).unwrap();
        eprintln!(
            "{}: the file system stores holes; not testing a {length}-byte file",
            dir.display()
        );
        return None;
    }
    Some(path)
}

/// `int iFileSize` holds the file's length: from 2 GiB on it is negative (`new` throws
/// `std::bad_alloc`), and from 4 GiB on it wraps (a file of 4 GiB + 507 bytes is read as its first
/// 507). The files are the control file and a hole, so they cost no disk and are read at once:
/// bvhview stops at the first zero after the rows, and `bvh::article` reads what the article
/// would, 507 bytes at most. (Linux; skipped, with a message, where holes are not supported.)
#[cfg(target_os = "linux")]
#[test]
fn files_of_2_and_4_gib_are_read_to_their_end() {
    let dir = tempfile::tempdir().unwrap();
    for (length, verdict) in [
        (
            2_500_000_000u64,
            "crashes on it: the file is 2500000000 bytes long, which int iFileSize holds as \
             -1794967296: new unsigned char[iFileSize] throws std::bad_alloc, and the program aborts",
        ),
        (
            (4u64 << 30) + 507,
            "misreads it: it reads only the first 507 of the file's 4294967803 bytes: int \
             iFileSize keeps the length modulo 4 GiB",
        ),
    ] {
        let Some(path) = sparse_control(dir.path(), length) else {
            continue;
        };
        let error = bvhview::bvh::load_file(&path, Default::default())
            .err()
            .unwrap();
        assert_eq!(
            error.to_string(),
            format!(
                "{}:21:1: found a NUL byte after the last frame: from here on the file is not text",
                path.display()
            )
        );
        let out = bvhview(&["info", path.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2));
        assert_eq!(
            verdict_of(&path),
            format!("// what the article's program does with this file: {verdict}")
        );
        // What the article reads of the second file is the control file, whole.
        let article = bvhview::bvh::article::run_file(&path, None).unwrap();
        assert_eq!(article.joints.is_some(), length > 1 << 32);
        std::fs::remove_file(&path).unwrap();
    }
}

/// The article keeps 22 bytes of a name; bvhview keeps the whole name up to 1024 bytes
/// (`limits::MAX_NAME_BYTES`, what TEACHING.md's Part 4 says of `new_node`) and refuses a longer
/// one where it stands.
#[test]
fn names_of_up_to_1024_bytes_are_kept_longer_ones_refused() {
    let control = std::fs::read_to_string(edge("article_base_crlf.bvh")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for length in [1024, 1025] {
        let name = "N".repeat(length);
        let path = dir.path().join(format!("name_{length}.bvh"));
        std::fs::write(
            &path,
            control.replace("JOINT Chest", &format!("JOINT {name}")),
        )
        .unwrap();
        match bvhview::bvh::load_file(&path, Default::default()) {
            Ok(bvh) => {
                assert_eq!(length, 1024);
                assert_eq!(bvh.skeleton.joints[1].name, name);
            }
            Err(error) => {
                assert_eq!(length, 1025);
                assert_eq!(
                    error.to_string(),
                    format!(
                        "{}:6:8: a name of 1025 bytes; names are at most 1024 bytes",
                        path.display()
                    )
                );
            }
        }
    }
}
