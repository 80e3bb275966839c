//! One reading of the body: the whole reading of each naming family's sample
//! skeleton (tests/body/, made by `tests/body/make.py`, and the repository's real files), the
//! doubts said when it is weak, a four-legged body refused onto a person, and the dataset's feet,
//! `--ground` and `--quat-continuous`.

use crate::common::bvhview_command;
use bvhview::Take;
use bvhview::model::body::{Body, Doubt};
use bvhview::model::pose::OffsetMode;

/// Each file and its reading, as `info`'s `body:` line says it (split at `; `).
const READINGS: &[(&str, &[&str])] = &[
    (
        "tests/body/bandai.bvh",
        &[
            "from names; ",
            "hips Hips; ",
            "spine Spine Chest; ",
            "neck Neck; ",
            "head Head; ",
            "left arm Shoulder_L > UpperArm_L > LowerArm_L > Hand_L; ",
            "left leg UpperLeg_L > LowerLeg_L > Foot_L > Toes_L; ",
            "right arm Shoulder_R > UpperArm_R > LowerArm_R > Hand_R; ",
            "right leg UpperLeg_R > LowerLeg_R > Foot_R > Toes_R; ",
            "feet Foot_L Toes_L Foot_R Toes_R",
        ],
    ),
    (
        "tests/body/biped_elephant.bvh",
        &[
            "from names; ",
            "hips Bip01 Pelvis; ",
            "spine Bip01 Spine Bip01 Spine1; ",
            "neck Bip01 Neck; ",
            "head Bip01 Head; ",
            "left arm Bip01 L Clavicle > Bip01 L UpperArm > Bip01 L Forearm > Bip01 L Hand; ",
            "left leg Bip01 L Thigh > Bip01 L Calf > Bip01 L Foot > none; ",
            "right arm Bip01 R Clavicle > Bip01 R UpperArm > Bip01 R Forearm > Bip01 R Hand; ",
            "right leg Bip01 R Thigh > Bip01 R Calf > Bip01 R Foot > none; ",
            "feet Bip01 L Foot Bip01 L Foot_End Bip01 R Foot Bip01 R Foot_End",
        ],
    ),
    (
        "tests/body/biped_human.bvh",
        &[
            "from names; ",
            "hips Bip01 Pelvis; ",
            "spine Bip01 Spine Bip01 Spine1 Bip01 Spine2; ",
            "neck Bip01 Neck; ",
            "head Bip01 Head; ",
            "left arm Bip01 L Clavicle > Bip01 L UpperArm > Bip01 L Forearm > Bip01 L Hand; ",
            "left leg Bip01 L Thigh > Bip01 L Calf > Bip01 L Foot > Bip01 L Toe0; ",
            "right arm Bip01 R Clavicle > Bip01 R UpperArm > Bip01 R Forearm > Bip01 R Hand; ",
            "right leg Bip01 R Thigh > Bip01 R Calf > Bip01 R Foot > Bip01 R Toe0; ",
            "left fingers thumb Bip01 L Finger0; ",
            "right fingers thumb Bip01 R Finger0; ",
            "feet Bip01 L Foot Bip01 L Toe0 Bip01 R Foot Bip01 R Toe0",
        ],
    ),
    (
        "tests/body/cgspeed_lowercase.bvh",
        &[
            "from names; ",
            "hips hip; ",
            "spine lowerback upperback thorax; ",
            "neck lowerneck; ",
            "head head; ",
            "left arm lclavicle > lshoulder > lelbow > lwrist; ",
            "left leg lbuttock > lknee > lankle > ltoe; ",
            "right arm rclavicle > rshoulder > relbow > rwrist; ",
            "right leg rbuttock > rknee > rankle > rtoe; ",
            "feet lankle ltoe rankle rtoe",
        ],
    ),
    (
        "tests/body/cmu.bvh",
        &[
            "from names; ",
            "hips Hips; ",
            "spine LowerBack Spine Spine1; ",
            "neck Neck; ",
            "head Head; ",
            "left arm LeftShoulder > LeftArm > LeftForeArm > LeftHand; ",
            "left leg LeftUpLeg > LeftLeg > LeftFoot > LeftToeBase; ",
            "right arm RightShoulder > RightArm > RightForeArm > RightHand; ",
            "right leg RightUpLeg > RightLeg > RightFoot > RightToeBase; ",
            "feet LeftFoot LeftToeBase RightFoot RightToeBase",
        ],
    ),
    (
        "tests/body/daz_poser_secondlife.bvh",
        &[
            "from names; ",
            "hips hip; ",
            "spine abdomen chest; ",
            "neck neck; ",
            "head head; ",
            "left arm lCollar > lShldr > lForeArm > lHand; ",
            "left leg lThigh > lShin > lFoot > lToe; ",
            "right arm rCollar > rShldr > rForeArm > rHand; ",
            "right leg rThigh > rShin > rFoot > rToe; ",
            "feet lFoot lToe rFoot rToe",
        ],
    ),
    (
        "tests/body/lafan1.bvh",
        &[
            "from names; ",
            "hips Hips; ",
            "spine Spine Spine1 Spine2; ",
            "neck Neck; ",
            "head Head; ",
            "left arm LeftShoulder > LeftArm > LeftForeArm > LeftHand; ",
            "left leg LeftUpLeg > LeftLeg > LeftFoot > LeftToe; ",
            "right arm RightShoulder > RightArm > RightForeArm > RightHand; ",
            "right leg RightUpLeg > RightLeg > RightFoot > RightToe; ",
            "feet LeftFoot LeftToe RightFoot RightToe",
        ],
    ),
    (
        "tests/body/makehuman.bvh",
        &[
            "from names; ",
            "hips Root; ",
            "spine Spine1 Spine2 Spine3; ",
            "neck Neck; ",
            "head Head; ",
            "left arm Clavicle_L > UpArm_L > LoArm_L > Hand_L; ",
            "left leg UpLeg_L > LoLeg_L > Foot_L > Toe_L; ",
            "right arm Clavicle_R > UpArm_R > LoArm_R > Hand_R; ",
            "right leg UpLeg_R > LoLeg_R > Foot_R > Toe_R; ",
            "feet Foot_L Toe_L Foot_R Toe_R",
        ],
    ),
    (
        "tests/body/mixamo.bvh",
        &[
            "from names; ",
            "hips mixamorig:Hips; ",
            "spine mixamorig:Spine mixamorig:Spine1 mixamorig:Spine2; ",
            "neck mixamorig:Neck; ",
            "head mixamorig:Head; ",
            "left arm mixamorig:LeftShoulder > mixamorig:LeftArm > mixamorig:LeftForeArm > mixamorig:LeftHand; ",
            "left leg mixamorig:LeftUpLeg > mixamorig:LeftLeg > mixamorig:LeftFoot > mixamorig:LeftToeBase; ",
            "right arm mixamorig:RightShoulder > mixamorig:RightArm > mixamorig:RightForeArm > mixamorig:RightHand; ",
            "right leg mixamorig:RightUpLeg > mixamorig:RightLeg > mixamorig:RightFoot > mixamorig:RightToeBase; ",
            "feet mixamorig:LeftFoot mixamorig:LeftToeBase mixamorig:RightFoot mixamorig:RightToeBase",
        ],
    ),
    (
        "tests/body/optitrack.bvh",
        &[
            "from names; ",
            "hips Skeleton1_Hip; ",
            "spine Skeleton1_Ab Skeleton1_Chest; ",
            "neck Skeleton1_Neck; ",
            "head Skeleton1_Head; ",
            "left arm Skeleton1_LShoulder > Skeleton1_LUArm > Skeleton1_LFArm > Skeleton1_LHand; ",
            "left leg Skeleton1_LThigh > Skeleton1_LShin > Skeleton1_LFoot > Skeleton1_LToe; ",
            "right arm Skeleton1_RShoulder > Skeleton1_RUArm > Skeleton1_RFArm > Skeleton1_RHand; ",
            "right leg Skeleton1_RThigh > Skeleton1_RShin > Skeleton1_RFoot > Skeleton1_RToe; ",
            "feet Skeleton1_LFoot Skeleton1_LToe Skeleton1_RFoot Skeleton1_RToe",
        ],
    ),
    (
        "tests/body/perception_neuron.bvh",
        &[
            "from names; ",
            "hips Hips; ",
            "spine Spine Spine1 Spine2; ",
            "neck Neck; ",
            "head Head; ",
            "left arm LeftShoulder > LeftArm > LeftForeArm > LeftHand; ",
            "left leg LeftUpLeg > LeftLeg > LeftFoot > none; ",
            "right arm RightShoulder > RightArm > RightForeArm > RightHand; ",
            "right leg RightUpLeg > RightLeg > RightFoot > none; ",
            "feet LeftFoot LeftFoot_End RightFoot RightFoot_End",
        ],
    ),
    (
        "tests/body/rigify.bvh",
        &[
            "from names; ",
            "hips DEF-spine; ",
            "spine DEF-spine.001 DEF-spine.002 DEF-spine.003; ",
            "neck DEF-spine.004; ",
            "head DEF-spine.006; ",
            "left arm DEF-shoulder.L > DEF-upper_arm.L > DEF-forearm.L > DEF-hand.L; ",
            "left leg DEF-thigh.L > DEF-shin.L > DEF-foot.L > DEF-toe.L; ",
            "right arm DEF-shoulder.R > DEF-upper_arm.R > DEF-forearm.R > DEF-hand.R; ",
            "right leg DEF-thigh.R > DEF-shin.R > DEF-foot.R > DEF-toe.R; ",
            "feet DEF-foot.L DEF-toe.L DEF-foot.R DEF-toe.R",
        ],
    ),
    (
        "tests/body/rokoko.bvh",
        &[
            "from names; ",
            "hips Hips; ",
            "spine Spine Spine1 Spine2 Spine3; ",
            "neck Neck; ",
            "head Head; ",
            "left arm LeftShoulder > LeftArm > LeftForeArm > LeftHand; ",
            "left leg LeftUpLeg > LeftLeg > LeftFoot > LeftToe; ",
            "right arm RightShoulder > RightArm > RightForeArm > RightHand; ",
            "right leg RightUpLeg > RightLeg > RightFoot > RightToe; ",
            "feet LeftFoot LeftToe RightFoot RightToe",
        ],
    ),
    (
        "tests/body/smpl.bvh",
        &[
            "from names; ",
            "hips pelvis; ",
            "spine spine1 spine2 spine3; ",
            "neck neck; ",
            "head head; ",
            "left arm left_collar > left_shoulder > left_elbow > left_wrist; ",
            "left leg left_hip > left_knee > left_ankle > left_foot; ",
            "right arm right_collar > right_shoulder > right_elbow > right_wrist; ",
            "right leg right_hip > right_knee > right_ankle > right_foot; ",
            "feet left_ankle left_foot right_ankle right_foot",
        ],
    ),
    (
        "tests/body/xsens.bvh",
        &[
            "from names; ",
            "hips Pelvis; ",
            "spine L5 L3 T12 T8; ",
            "neck Neck; ",
            "head Head; ",
            "left arm LeftShoulder > LeftUpperArm > LeftForeArm > LeftHand; ",
            "left leg LeftUpperLeg > LeftLowerLeg > LeftFoot > LeftToe; ",
            "right arm RightShoulder > RightUpperArm > RightForeArm > RightHand; ",
            "right leg RightUpperLeg > RightLowerLeg > RightFoot > RightToe; ",
            "feet LeftFoot LeftToe RightFoot RightToe",
        ],
    ),
    (
        "tests/data/bvh/makehuman_walk1.bvh",
        &[
            "from names; ",
            "hips Root; ",
            "spine Spine1 Spine2 Spine3; ",
            "neck Neck; ",
            "head Head; ",
            "left arm Clavicle_L > UpArm_L > LoArm_L > Hand_L; ",
            "left leg UpLeg_L > LoLeg_L > Foot_L > Toe_L; ",
            "right arm Clavicle_R > UpArm_R > LoArm_R > Hand_R; ",
            "right leg UpLeg_R > LoLeg_R > Foot_R > Toe_R; ",
            "left fingers thumb Thumb1_L Thumb2_L Thumb3_L, index Index1_L Index2_L Index3_L, middle Middle1_L Middle2_L Middle3_L, ring Ring1_L Ring2_L Ring3_L, pinky Pinky1_L Pinky2_L Pinky3_L; ",
            "right fingers thumb Thumb1_R Thumb2_R Thumb3_R, index Index1_R Index2_R Index3_R, middle Middle1_R Middle2_R Middle3_R, ring Ring1_R Ring2_R Ring3_R, pinky Pinky1_R Pinky2_R Pinky3_R; ",
            "feet Foot_L Toe_L Foot_R Toe_R",
        ],
    ),
    (
        "tests/data/bvh/makehuman_tpose.bvh",
        &[
            "from names; ",
            "hips root; ",
            "spine spine05 spine04 spine03 spine02 spine01; ",
            "neck neck01; ",
            "head head; ",
            "left arm clavicle.L > upperarm01.L > lowerarm01.L > wrist.L; ",
            "left leg upperleg01.L > lowerleg01.L > foot.L > toe1-1.L; ",
            "right arm clavicle.R > upperarm01.R > lowerarm01.R > wrist.R; ",
            "right leg upperleg01.R > lowerleg01.R > foot.R > toe1-1.R; ",
            "left fingers thumb finger1-1.L finger1-2.L finger1-3.L, index finger2-1.L finger2-2.L finger2-3.L, middle finger3-1.L finger3-2.L finger3-3.L, ring finger4-1.L finger4-2.L finger4-3.L, pinky finger5-1.L finger5-2.L finger5-3.L; ",
            "right fingers thumb finger1-1.R finger1-2.R finger1-3.R, index finger2-1.R finger2-2.R finger2-3.R, middle finger3-1.R finger3-2.R finger3-3.R, ring finger4-1.R finger4-2.R finger4-3.R, pinky finger5-1.R finger5-2.R finger5-3.R; ",
            "feet foot.R toe1-1.R foot.L toe1-1.L",
        ],
    ),
    (
        "tests/data/asf_amc/heiden_12.asf",
        &[
            "from names; ",
            "hips root; ",
            "spine lowerback upperback thorax; ",
            "neck lowerneck; ",
            "head head; ",
            "left arm lclavicle > lhumerus > lradius > lwrist; ",
            "left leg lfemur > ltibia > lfoot > ltoes; ",
            "right arm rclavicle > rhumerus > rradius > rwrist; ",
            "right leg rfemur > rtibia > rfoot > rtoes; ",
            "left fingers thumb lthumb, index lfingers; ",
            "right fingers thumb rthumb, index rfingers; ",
            "feet lfoot ltoes rfoot rtoes",
        ],
    ),
    (
        "tests/data/bvh/bvh11_131_01.bvh",
        &[
            "from names; ",
            "hips Hips; ",
            "spine lowerback Chest Chest2; ",
            "neck lowerneck; ",
            "head Head; ",
            "left arm LeftCollar > LeftShoulder > LeftElbow > LeftWrist; ",
            "left leg LeftHip > LeftKnee > LeftAnkle > LeftToe; ",
            "right arm RightCollar > RightShoulder > RightElbow > RightWrist; ",
            "right leg RightHip > RightKnee > RightAnkle > RightToe; ",
            "left fingers thumb LThumb; ",
            "right fingers thumb RThumb; ",
            "feet LeftAnkle LeftToe RightAnkle RightToe",
        ],
    ),
    (
        "tests/data/bvh/opencollar_cutie.bvh",
        &[
            "from names; ",
            "hips hip; ",
            "spine mSpine1 mSpine2 abdomen mSpine3 mSpine4 chest; ",
            "neck neck; ",
            "head head; ",
            "left arm lCollar > lShldr > lForeArm > lHand; ",
            "left leg lThigh > lShin > lFoot > none; ",
            "right arm rCollar > rShldr > rForeArm > rHand; ",
            "right leg rThigh > rShin > rFoot > none; ",
            "left fingers thumb mHandThumb1Left mHandThumb2Left mHandThumb3Left, index mHandIndex1Left mHandIndex2Left mHandIndex3Left, middle mHandMiddle1Left mHandMiddle2Left mHandMiddle3Left, ring mHandRing1Left mHandRing2Left mHandRing3Left, pinky mHandPinky1Left mHandPinky2Left mHandPinky3Left; ",
            "right fingers thumb mHandThumb1Right mHandThumb2Right mHandThumb3Right, index mHandIndex1Right mHandIndex2Right mHandIndex3Right, middle mHandMiddle1Right mHandMiddle2Right mHandMiddle3Right, ring mHandRing1Right mHandRing2Right mHandRing3Right, pinky mHandPinky1Right mHandPinky2Right mHandPinky3Right; ",
            "feet rFoot rFoot_End lFoot lFoot_End",
        ],
    ),
    (
        "tests/data/bvh/assimp_01_01.bvh",
        &[
            "from names; ",
            "hips Hips; ",
            "spine LowerBack Spine Spine1; ",
            "neck Neck; ",
            "head Head; ",
            "left arm LeftShoulder > LeftArm > LeftForeArm > LeftHand; ",
            "left leg LeftUpLeg > LeftLeg > LeftFoot > LeftToeBase; ",
            "right arm RightShoulder > RightArm > RightForeArm > RightHand; ",
            "right leg RightUpLeg > RightLeg > RightFoot > RightToeBase; ",
            "left fingers thumb LThumb; ",
            "right fingers thumb RThumb; ",
            "feet LeftFoot LeftToeBase RightFoot RightToeBase",
        ],
    ),
];

#[test]
fn every_family_is_read_whole() {
    for (path, parts) in READINGS {
        let take = Take::open(path).unwrap();
        let body = Body::of(&take.skeleton);
        assert_eq!(body.summary(&take.skeleton), parts.concat(), "{path}");
        // Every family's sample is a person standing: nothing is doubted.
        if !path.contains("elephant") {
            assert_eq!(
                body.doubts(&take.skeleton, &take.motion, OffsetMode::Replace),
                Vec::new(),
                "{path}"
            );
        }
        // `info` says the same line.
        let out = bvhview_command().args(["info", path]).output().unwrap();
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(
            text.lines()
                .any(|l| l.strip_prefix("body:").map(str::trim) == Some(&parts.concat()[..])),
            "{path}: {text}"
        );
    }
}

#[test]
fn a_four_legged_body_is_said_and_refused_onto_a_person_unless_insisted() {
    let path = "tests/body/biped_elephant.bvh";
    let take = Take::open(path).unwrap();
    let doubts = Body::of(&take.skeleton).doubts(&take.skeleton, &take.motion, OffsetMode::Replace);
    assert_eq!(
        doubts,
        [Doubt::NotBiped(
            "its head lies 80° from the legs' up; four-legged?".to_string()
        )]
    );
    let info = bvhview_command().args(["info", path]).output().unwrap();
    let text = String::from_utf8(info.stdout).unwrap();
    assert!(
        text.contains(
            "  - body: not a two-legged body: its head lies 80° from the legs' up; four-legged?\n"
        ),
        "{text}"
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("on_smpl.bvh");
    let refused = bvhview_command()
        .args(["retarget", path, "--onto", "smpl22", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(2));
    assert_eq!(
        String::from_utf8(refused.stderr).unwrap(),
        "bvhview: tests/body/biped_elephant.bvh: not a two-legged body (its head lies 80° from \
         the legs' up; four-legged?), and smpl22 is one: its limbs would be carried over as a \
         person's; `--any-body` retargets it anyway\n"
    );
    assert!(!out.exists());
    let insisted = bvhview_command()
        .args([
            "retarget",
            path,
            "--onto",
            "smpl22",
            "--any-body",
            "-q",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(insisted.status.code(), Some(0));
    assert_eq!(Take::open(&out).unwrap().skeleton.joints.len(), 22 + 5);
    // A person onto a person is never asked.
    let person = bvhview_command()
        .args([
            "retarget",
            "tests/body/biped_human.bvh",
            "--onto",
            "smpl22",
            "-q",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(person.status.code(), Some(0), "{:?}", person);
}

/// A four-legged character (the elephant with the generated skin as its mesh): a person's
/// walk on it is refused as onto the elephant's skeleton, and `--any-body` puts it on.
#[cfg(feature = "gltf")]
#[test]
fn a_person_on_a_four_legged_character_is_refused_unless_insisted() {
    let elephant = "tests/body/biped_elephant.bvh";
    let walk = "tests/data/bvh/bvhparser_walk_01.bvh";
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).display().to_string();
    let run = |args: &[&str]| bvhview_command().args(args).output().unwrap();
    let character = path("elephant.glb");
    let made = run(&["convert", elephant, "--skin", "-q", "-o", &character]);
    assert!(made.status.success(), "{made:?}");
    let picture = path("walk_on_elephant.png");
    let snapshot = |extra: &[&str]| {
        let mut args = vec![
            "snapshot",
            walk,
            "--character",
            &character,
            "--size",
            "64x64",
        ];
        args.extend_from_slice(extra);
        args.extend(["-o", &picture]);
        run(&args)
    };
    let out = snapshot(&[]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("a two-legged body, and ")
            && stderr.contains("`--any-body` retargets it anyway"),
        "{stderr}"
    );
    assert!(!std::path::Path::new(&picture).exists());
    let out = snapshot(&["--any-body", "-q"]);
    assert!(out.status.success(), "{out:?}");
}

/// One rule both ways, everywhere a take goes onto another skeleton: a person's walk onto a
/// four-legged target (`retarget --onto`, a character, `dataset --onto`) was put on without a
/// word where the reverse was refused; now each refuses with the reason and `--any-body` goes
/// ahead.
#[test]
fn a_person_onto_a_four_legged_body_is_refused_everywhere_unless_insisted() {
    let elephant = "tests/body/biped_elephant.bvh";
    let walk = "tests/data/bvh/bvhparser_walk_01.bvh";
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).display().to_string();
    let run = |args: &[&str]| bvhview_command().args(args).output().unwrap();
    let said = "bvhview: tests/data/bvh/bvhparser_walk_01.bvh: a two-legged body, and \
                tests/body/biped_elephant.bvh is not (its head lies 80° from the legs' up; \
                four-legged?): a person's limbs would be carried onto it as if it were one; \
                `--any-body` retargets it anyway\n";
    let refused = |out: &std::process::Output, written: &str| {
        assert_eq!(out.status.code(), Some(2), "{out:?}");
        assert_eq!(String::from_utf8_lossy(&out.stderr), said);
        assert!(!std::path::Path::new(written).exists());
    };
    let on = path("on_elephant.bvh");
    refused(
        &run(&["retarget", walk, "--onto", elephant, "-o", &on]),
        &on,
    );
    let insisted = run(&[
        "retarget",
        walk,
        "--onto",
        elephant,
        "--any-body",
        "-q",
        "-o",
        &on,
    ]);
    assert!(insisted.status.success(), "{insisted:?}");
    // A dataset onto the elephant skips the walk with the reason, and takes it when insisted.
    let takes = path("takes");
    std::fs::create_dir(&takes).unwrap();
    std::fs::copy(walk, dir.path().join("takes/walk.bvh")).unwrap();
    let out = run(&[
        "dataset",
        &takes,
        "--onto",
        elephant,
        "-o",
        &path("skipped.ds"),
    ]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("`--any-body` retargets it anyway"),
        "{out:?}"
    );
    let out = run(&[
        "dataset",
        &takes,
        "--onto",
        elephant,
        "--any-body",
        "-q",
        "-o",
        &path("made.ds"),
    ]);
    assert!(out.status.success(), "{out:?}");
    assert!(dir.path().join("made.ds/manifest.json").is_file());
}

/// Joints as `(name, parent, offset)`, one frame of zeros.
fn skeleton_text(joints: &[(&str, Option<&str>, [f32; 3])]) -> String {
    fn emit(
        joints: &[(&str, Option<&str>, [f32; 3])],
        at: usize,
        depth: usize,
        out: &mut String,
        channels: &mut usize,
    ) {
        let (name, parent, [x, y, z]) = joints[at];
        let pad = "  ".repeat(depth);
        let kind = if parent.is_none() { "ROOT" } else { "JOINT" };
        out.push_str(&format!(
            "{pad}{kind} {name}\n{pad}{{\n{pad}  OFFSET {x} {y} {z}\n"
        ));
        if parent.is_none() {
            out.push_str(&format!(
                "{pad}  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
            ));
            *channels += 6;
        } else {
            out.push_str(&format!(
                "{pad}  CHANNELS 3 Zrotation Xrotation Yrotation\n"
            ));
            *channels += 3;
        }
        let children: Vec<usize> = (0..joints.len())
            .filter(|&c| joints[c].1 == Some(name))
            .collect();
        if children.is_empty() {
            out.push_str(&format!(
                "{pad}  End Site\n{pad}  {{\n{pad}    OFFSET 0 -5 0\n{pad}  }}\n"
            ));
        }
        for c in children {
            emit(joints, c, depth + 1, out, channels);
        }
        out.push_str(&format!("{pad}}}\n"));
    }
    let mut text = String::from("HIERARCHY\n");
    let mut channels = 0;
    emit(joints, 0, 0, &mut text, &mut channels);
    text.push_str("MOTION\nFrames: 1\nFrame Time: 0.04\n");
    text.push_str(&vec!["0"; channels].join(" "));
    text.push('\n');
    text
}

#[test]
fn a_weak_reading_names_what_is_missing() {
    // One leg, and a left arm without a right one.
    let text = skeleton_text(&[
        ("Hips", None, [0.0, 95.0, 0.0]),
        ("LeftUpLeg", Some("Hips"), [10.0, 0.0, 0.0]),
        ("LeftLeg", Some("LeftUpLeg"), [0.0, -42.0, 0.0]),
        ("LeftFoot", Some("LeftLeg"), [0.0, -42.0, 0.0]),
        ("Spine", Some("Hips"), [0.0, 20.0, 0.0]),
        ("Head", Some("Spine"), [0.0, 40.0, 0.0]),
        ("LeftArm", Some("Spine"), [15.0, 30.0, 0.0]),
        ("LeftForeArm", Some("LeftArm"), [25.0, 0.0, 0.0]),
    ]);
    let take = bvhview::bvh::load_bytes(text.as_bytes(), "one_leg.bvh").unwrap();
    let body = Body::of(&take.skeleton);
    let said: Vec<String> = body
        .doubts(&take.skeleton, &take.motion, OffsetMode::Replace)
        .iter()
        .map(ToString::to_string)
        .collect();
    assert_eq!(
        said,
        [
            "no two legs read (thigh and shin on each side)",
            "sides undecided: a left upper arm but no right upper arm",
            "sides undecided: a left forearm but no right forearm",
            "sides undecided: a left thigh but no right thigh",
            "sides undecided: a left shin but no right shin",
            "sides undecided: a left foot but no right foot",
        ]
    );
    assert_eq!(body.foot_points(&take.skeleton), Vec::<usize>::new());
}

/// The clips of every take in `files` (name, text), compiled with `options`, by file name.
fn compile(
    files: &[(&str, String)],
    options: &bvhview::dataset::Options,
) -> Vec<(String, bvhview::dataset::Clip)> {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let mut clips: Vec<(String, bvhview::dataset::Clip)> = bvhview::dataset::takes(dir.path())
        .unwrap()
        .iter()
        .map(|item| {
            let name = item
                .path
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            (
                name,
                bvhview::dataset::compile_take(dir.path(), item, options).unwrap(),
            )
        })
        .collect();
    clips.sort_by(|a, b| a.0.cmp(&b.0));
    clips
}

#[test]
fn dataset_feet_come_from_the_legs_and_a_body_without_them_is_said() {
    let read = |path: &str| std::fs::read_to_string(path).unwrap();
    let clips = compile(
        &[
            ("lafan1.bvh", read("tests/body/lafan1.bvh")),
            (
                "perception_neuron.bvh",
                read("tests/body/perception_neuron.bvh"),
            ),
            ("simple.bvh", read("tests/data/bvh/bvhanim_test_simple.bvh")),
        ],
        &bvhview::dataset::Options::default(),
    );
    let feet = |clip: &bvhview::dataset::Clip| -> Vec<String> {
        clip.topology
            .feet
            .iter()
            .map(|&p| clip.topology.joints[p as usize].clone())
            .collect()
    };
    assert_eq!(
        feet(&clips[0].1),
        ["LeftFoot", "LeftToe", "RightFoot", "RightToe"]
    );
    // No toe joint: the End Site below the ankle.
    assert_eq!(
        feet(&clips[1].1),
        ["LeftFoot", "LeftFoot_End", "RightFoot", "RightFoot_End"]
    );
    assert!(
        clips[0].1.about.warnings.is_empty(),
        "{:?}",
        clips[0].1.about.warnings
    );
    assert_eq!(feet(&clips[2].1), Vec::<String>::new());
    assert_eq!(
        clips[2].1.about.warnings,
        [
            "feet: no ankle read below each leg; contacts are for points guessed from the rest \
          pose (none found); name them with `feet`"
        ]
    );
}

/// A take on the LaFAN1 sample whose hips sink 30 cm below the floor and turn
/// about y from 150° through 180° to 210° (a quaternion's w crosses 0 at 180°).
fn sunk_and_turning() -> String {
    let text = std::fs::read_to_string("tests/body/lafan1.bvh").unwrap();
    let (head, rows) = text.split_once("MOTION\n").unwrap();
    let zero_row = rows.lines().nth(2).unwrap();
    let values: Vec<&str> = zero_row.split(' ').collect();
    let mut out = format!("{head}MOTION\nFrames: 7\nFrame Time: 0.0333333\n");
    for f in 0..7 {
        let mut row: Vec<String> = values.iter().map(|v| v.to_string()).collect();
        row[1] = format!("{}", 95.0 - 30.0);
        // The root's channels: X Y Z position, then Z, Y, X rotation.
        row[4] = format!("{}", 150.0 + 10.0 * f as f32);
        out.push_str(&row.join(" "));
        out.push('\n');
    }
    out
}

#[test]
fn ground_puts_the_lowest_foot_on_the_floor_and_moves_the_root_with_it() {
    let files = [("sunk.bvh", sunk_and_turning())];
    let plain = &compile(&files, &bvhview::dataset::Options::default())[0].1;
    let options = bvhview::dataset::Options {
        ground: true,
        ..Default::default()
    };
    let grounded = &compile(&files, &options)[0].1;
    let points = grounded.topology.joints.len();
    let lowest_foot = |clip: &bvhview::dataset::Clip| {
        (0..clip.frames)
            .flat_map(|f| {
                clip.topology
                    .feet
                    .iter()
                    .map(move |&p| (f * points + p as usize) * 3 + 1)
            })
            .map(|i| clip.positions[i])
            .fold(f32::INFINITY, f32::min)
    };
    // The toes sit 1 cm over the hips' 95 cm: sunk 30 cm, 0.29 m under y = 0 before.
    assert!(
        (lowest_foot(plain) + 0.29).abs() < 1e-5,
        "{}",
        lowest_foot(plain)
    );
    assert_eq!(lowest_foot(grounded), 0.0);
    // The root's translation is its world position, grounded alike; its x and z are untouched.
    for f in 0..grounded.frames {
        let position = &grounded.positions[f * points * 3..f * points * 3 + 3];
        let translation = &grounded.translations[f * 3..f * 3 + 3];
        assert_eq!(position, translation, "frame {f}");
        assert_eq!(plain.translations[f * 3], translation[0]);
        assert_eq!(plain.translations[f * 3 + 2], translation[2]);
    }
}

#[test]
fn quat_continuous_keeps_each_joints_sign_along_time() {
    let files = [("turning.bvh", sunk_and_turning())];
    let flips = |clip: &bvhview::dataset::Clip| {
        let width = clip.topology.rotated.len() * 4;
        let rows: Vec<&[f32]> = clip.rotations.chunks(width).collect();
        rows.windows(2)
            .flat_map(|w| {
                w[0].chunks(4)
                    .zip(w[1].chunks(4))
                    .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x * y).sum::<f32>())
            })
            .filter(|&dot| dot < 0.0)
            .count()
    };
    let quat = bvhview::dataset::Options {
        rotations: bvhview::model::pose::RotationKind::Quat,
        ..Default::default()
    };
    let signed = &compile(&files, &quat)[0].1;
    let continuous_options = bvhview::dataset::Options {
        quat_continuous: true,
        ..quat.clone()
    };
    let continuous = &compile(&files, &continuous_options)[0].1;
    // w ≥ 0 frame by frame flips the hips' sign where the turn passes 180°.
    assert_eq!(flips(signed), 1);
    assert_eq!(flips(continuous), 0);
    // The same rotations: each quaternion is the other or its negation.
    for (a, b) in signed
        .rotations
        .chunks(4)
        .zip(continuous.rotations.chunks(4))
    {
        assert!(
            a == b || a.iter().zip(b).all(|(x, y)| *x == -*y),
            "{a:?} {b:?}"
        );
    }
    // Asked of a kind without a sign, it is refused by name.
    let six_d = bvhview::dataset::Options {
        quat_continuous: true,
        ..Default::default()
    };
    let refused = six_d.check().unwrap_err();
    assert!(
        matches!(
            refused,
            bvhview::Error::InvalidArgument {
                name: "quat_continuous",
                ..
            }
        ),
        "{refused:?}"
    );
    assert_eq!(
        refused.to_string(),
        "quat_continuous: only quaternions have a sign to choose (rotations quat), not 6d"
    );
}

/// The lowest of the reading's foot points over a take.
fn lowest_foot(take: &Take) -> f32 {
    let feet = Body::of(&take.skeleton).foot_points(&take.skeleton);
    (0..take.frame_count())
        .flat_map(|f| {
            let world = bvhview::model::pose::world_positions(
                &take.skeleton,
                take.motion.frame(f),
                OffsetMode::Replace,
            );
            feet.iter().map(move |&p| world[p].y).collect::<Vec<f32>>()
        })
        .fold(f32::INFINITY, f32::min)
}

#[test]
fn a_retargeted_take_stands_on_its_own_feet_where_the_source_stood() {
    // The LaFAN1 sample with each toe's End Site 4 cm under the toe joint: the source's lowest
    // leg point is a tip the SMPL sample does not have. Legs of one length: no scaling.
    let text = std::fs::read_to_string("tests/body/lafan1.bvh")
        .unwrap()
        .replace("OFFSET 0 0 5\n", "OFFSET 0 -4 5\n")
        // Its toes 1 cm over y = 0 at rest: lowered onto it.
        .replace("\n0 95 0 ", "\n0 94 0 ")
        .replace("\n2 95 1 ", "\n2 94 1 ");
    assert_eq!(text.matches("OFFSET 0 -4 5").count(), 2);
    let dir = tempfile::tempdir().unwrap();
    let (source, out) = (
        dir.path().join("tiptoe.bvh"),
        dir.path().join("on_smpl.bvh"),
    );
    std::fs::write(&source, text).unwrap();
    let run = bvhview_command()
        .arg("retarget")
        .arg(&source)
        .args(["--onto", "tests/body/smpl.bvh", "-q", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.success(), "{run:?}");
    let (source, target) = (Take::open(&source).unwrap(), Take::open(&out).unwrap());
    assert_eq!(lowest_foot(&source), 0.0);
    // Placed by the source's tips, the target's toes went 4 cm under: the body's reading places them.
    assert!(
        lowest_foot(&target).abs() < 1e-4,
        "{}",
        lowest_foot(&target)
    );
}

#[test]
fn fingers_are_carried_by_role_between_families() {
    use bvhview::model::body::{Role, Side};
    use bvhview::retarget::{self, Map, Target, Ups};
    // Mixamo's fingers (LeftHandIndex1…) onto MakeHuman's (Index1_L…): no name in common.
    let source = Take::open("tests/data/bvh/bvhpython_test_freebvh.bvh").unwrap();
    let target = Target::load("tests/data/bvh/makehuman_walk1.bvh", u64::MAX).unwrap();
    let map = Map::guess(&source.skeleton, &target.skeleton);
    let name = |t: usize| target.skeleton.joints[t].name.as_str();
    let source_name = |t: usize| {
        source.skeleton.joints[map.source_of[t].unwrap()]
            .name
            .as_str()
    };
    let index = map
        .target_body
        .joint(Role::Finger(Side::Left, 1, 0))
        .unwrap();
    assert_eq!(
        (source_name(index), name(index)),
        ("mixamorig:LeftHandIndex1", "Index1_L")
    );
    let fingers: Vec<usize> = (0..5)
        .flat_map(|f| (0..3).map(move |b| (f, b)))
        .flat_map(|(f, b)| [Side::Left, Side::Right].map(|s| Role::Finger(s, f, b)))
        .filter_map(|role| map.target_body.joint(role))
        .collect();
    assert_eq!(fingers.len(), 30);
    assert!(fingers.iter().all(|&t| map.source_of[t].is_some()));
    // Each finger bone's direction follows the source's, as the arms' do.
    let ups = Ups {
        source: source.stance(OffsetMode::Replace).up,
        target: target.up,
    };
    let finger_errors = |out: &(bvhview::Skeleton, bvhview::Motion)| -> Vec<f64> {
        let errors =
            retarget::direction_errors(&source.skeleton, &source.motion, &out.0, &out.1, &map, ups);
        retarget::bones(&source.skeleton, &target.skeleton, &map)
            .iter()
            .zip(errors)
            .filter(|((t, _), _)| fingers.contains(t))
            .flat_map(|(_, e)| e)
            .collect()
    };
    let median = |mut e: Vec<f64>| {
        e.sort_by(f64::total_cmp);
        e[e.len() / 2]
    };
    let mapped = target
        .apply(
            "mixamo",
            &source.skeleton,
            &source.motion,
            &[],
            Default::default(),
            2,
        )
        .map(|put| (put.skeleton, put.motion))
        .unwrap();
    let by_role = median(finger_errors(&mapped));
    // The fingers left out, as they were before the reading knew them: straight at rest.
    let left_out: Vec<(String, String)> = fingers
        .iter()
        .map(|&t| (source_name(t).to_string(), String::new()))
        .collect();
    let unmapped = target
        .apply(
            "mixamo",
            &source.skeleton,
            &source.motion,
            &left_out,
            Default::default(),
            2,
        )
        .map(|put| (put.skeleton, put.motion))
        .unwrap();
    let at_rest = median(finger_errors(&unmapped));
    assert!(by_role < 1.0, "fingers by role: median {by_role}°");
    assert!(at_rest > 10.0, "fingers at rest: median {at_rest}°");
    println!("finger direction error, median: by role {by_role:.2}°, left at rest {at_rest:.2}°");
}

#[test]
fn a_dataset_onto_one_skeleton_takes_a_map_and_records_both() {
    let dir = tempfile::tempdir().unwrap();
    let takes = dir.path().join("takes");
    std::fs::create_dir(&takes).unwrap();
    for family in ["lafan1", "mixamo"] {
        std::fs::copy(
            format!("tests/body/{family}.bvh"),
            takes.join(format!("{family}.bvh")),
        )
        .unwrap();
    }
    let (onto, plain) = (dir.path().join("onto"), dir.path().join("plain"));
    let run = bvhview_command()
        .arg("dataset")
        .arg(&takes)
        .args(["--onto", "smpl22", "--map", "LeftToe=", "-o"])
        .arg(&onto)
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(0), "{run:?}");
    let manifest = bvhview::dataset::read::read_manifest(&onto).unwrap();
    assert_eq!(manifest.options.onto.as_deref(), Some("smpl22"));
    assert_eq!(
        manifest.options.map.all,
        [("LeftToe".to_string(), String::new())]
    );
    // The pair names a LaFAN1 joint: Mixamo's take has none of that name and is skipped.
    assert_eq!(manifest.clips.len(), 1);
    assert_eq!(manifest.clips[0].about.source.path, "lafan1.bvh");
    assert_eq!(manifest.skipped.len(), 1);
    assert!(
        manifest.skipped[0]
            .error
            .starts_with("map: the source has no joint named \"LeftToe\""),
        "{}",
        manifest.skipped[0].error
    );
    // A dataset made onto a skeleton does not merge with one made without.
    let run = bvhview_command()
        .arg("dataset")
        .arg(&takes)
        .arg("-o")
        .arg(&plain)
        .arg("-q")
        .output()
        .unwrap();
    assert!(run.status.success());
    let merged = bvhview::dataset::merge::merge(
        &[onto.clone(), plain.clone()],
        &dir.path().join("merged"),
        bvhview::dataset::merge::Join::Folders,
    );
    assert!(
        merged
            .unwrap_err()
            .to_string()
            .contains("made with other options than"),
    );
    // --map alone is refused by clap, before any take is read.
    let alone = bvhview_command()
        .arg("dataset")
        .arg(&takes)
        .args(["--map", "LeftToe=", "-o"])
        .arg(dir.path().join("never"))
        .output()
        .unwrap();
    assert_eq!(alone.status.code(), Some(2));
}

#[test]
fn one_map_file_serves_a_folder_of_mixed_rigs_by_fingerprint() {
    let dir = tempfile::tempdir().unwrap();
    let takes = dir.path().join("takes");
    std::fs::create_dir(&takes).unwrap();
    let mut map = String::from("# each rig's left toe left out\n");
    for (family, toe) in [("lafan1", "LeftToe"), ("mixamo", "mixamorig:LeftToeBase")] {
        let path = format!("tests/body/{family}.bvh");
        std::fs::copy(&path, takes.join(format!("{family}.bvh"))).unwrap();
        // The fingerprint `info` prints.
        let info = bvhview_command().args(["info", &path]).output().unwrap();
        let text = String::from_utf8(info.stdout).unwrap();
        let fingerprint = text
            .lines()
            .find_map(|l| l.strip_prefix("fingerprint:"))
            .unwrap()
            .trim()
            .to_string();
        assert_eq!(
            fingerprint,
            Take::open(&path).unwrap().skeleton.fingerprint()
        );
        map.push_str(&format!("[skeleton.{fingerprint}]\n\"{toe}\" = \"\"\n"));
    }
    let map_file = dir.path().join("map.toml");
    std::fs::write(&map_file, &map).unwrap();
    let out = dir.path().join("ds");
    let run = bvhview_command()
        .arg("dataset")
        .arg(&takes)
        .args(["--onto", "smpl22", "-q", "--map"])
        .arg(&map_file)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(0), "{run:?}");
    let manifest = bvhview::dataset::read::read_manifest(&out).unwrap();
    // Each take took its own rig's pair: none is skipped.
    assert_eq!(manifest.clips.len(), 2);
    assert!(manifest.skipped.is_empty(), "{:?}", manifest.skipped);
    assert_eq!(manifest.options.map.by_skeleton.len(), 2);
    // The same pairs given for every skeleton skip both takes, each lacking the other's joint.
    let flat = dir.path().join("flat");
    let run = bvhview_command()
        .arg("dataset")
        .arg(&takes)
        .args([
            "--onto",
            "smpl22",
            "-q",
            "--map",
            "LeftToe=",
            "--map",
            "mixamorig:LeftToeBase=",
            "-o",
        ])
        .arg(&flat)
        .output()
        .unwrap();
    assert_eq!(run.status.code(), Some(2), "{run:?}");
}

/// `convert --ground` stands a take on its soles: each ankle and what is below it. The LaFAN1
/// sample with each toe's End Site 4 units under the toe joint: the tips touch y = 0 (the toe
/// joints, the reading's foot points, stand 4 above), and the figure's hands, lowered below
/// the feet in a squat, do not decide the floor.
#[test]
fn grounding_stands_the_soles_on_the_floor() {
    let text = std::fs::read_to_string("tests/body/lafan1.bvh")
        .unwrap()
        .replace("OFFSET 0 0 5\n", "OFFSET 0 -4 5\n")
        .replacen("OFFSET 9 0 0\n", "OFFSET 9 -200 0\n", 1);
    let take = bvhview::bvh::load_bytes(text.as_bytes(), "lafan1").unwrap();
    let skeleton = take.skeleton;
    let body = Body::of(&skeleton);
    let soles = body.sole_points(&skeleton);
    let named: Vec<&str> = soles
        .iter()
        .map(|&j| skeleton.joints[j].name.as_str())
        .collect();
    assert_eq!(
        named.iter().filter(|n| **n == "Site").count(),
        2,
        "{named:?}"
    );
    assert_eq!(soles.len(), 6, "{named:?}");
    // The left hand's tip 200 units down, far below the feet, is not the floor.
    let (grounded, motion) = bvhview::edit::ground(
        &skeleton,
        &take.motion,
        OffsetMode::Replace,
        bvhview::model::pose::Up::Y,
    )
    .unwrap();
    let mut lowest_sole = f32::INFINITY;
    let mut lowest_toe = f32::INFINITY;
    let feet = body.foot_points(&grounded);
    for f in 0..motion.frame_count() {
        let world =
            bvhview::model::pose::world_positions(&grounded, motion.frame(f), OffsetMode::Replace);
        lowest_sole = soles
            .iter()
            .map(|&j| world[j].y)
            .fold(lowest_sole, f32::min);
        lowest_toe = feet.iter().map(|&j| world[j].y).fold(lowest_toe, f32::min);
    }
    assert!(lowest_sole.abs() < 1e-4, "{lowest_sole}");
    assert!((lowest_toe - 4.0).abs() < 1e-3, "{lowest_toe}");
}

/// One sample per class the names alone misread (tests/body/make_classes.py): the whole
/// reading, what it doubts, and the up axis `info` says.
const CLASSES: &[(&str, &[&str], &[&str], &str)] = &[
    (
        // The upper arm is the bone that reaches the elbow, not the shoulder piece above it.
        "tests/body/makehuman_shoulder01.bvh",
        &[
            "from names; ",
            "hips root; ",
            "spine spine03 spine01; ",
            "neck neck01; ",
            "head head; ",
            "left arm clavicle.L > upperarm01.L > lowerarm01.L > wrist.L; ",
            "left leg upperleg01.L > lowerleg01.L > foot.L > toe1-1.L; ",
            "right arm clavicle.R > upperarm01.R > lowerarm01.R > wrist.R; ",
            "right leg upperleg01.R > lowerleg01.R > foot.R > toe1-1.R; ",
            "feet foot.L toe1-1.L foot.R toe1-1.R",
        ],
        &[],
        "y (sure: the figure spreads 163 along y and 18.0 along z over 2 frames)",
    ),
    (
        // Palms before the finger roots are no finger bone; the head above the face.
        "tests/body/rigify_palms_face.bvh",
        &[
            "from names; ",
            "hips DEF-spine; ",
            "spine DEF-spine.001 DEF-spine.002 DEF-spine.003; ",
            "neck DEF-spine.004; ",
            "head DEF-spine.006; ",
            "left arm DEF-shoulder.L > DEF-upper_arm.L > DEF-forearm.L > DEF-hand.L; ",
            "left leg DEF-thigh.L > DEF-shin.L > DEF-foot.L > DEF-toe.L; ",
            "right arm DEF-shoulder.R > DEF-upper_arm.R > DEF-forearm.R > DEF-hand.R; ",
            "right leg DEF-thigh.R > DEF-shin.R > DEF-foot.R > DEF-toe.R; ",
            "left fingers thumb DEF-thumb.01.L DEF-thumb.02.L DEF-thumb.03.L, \
             index DEF-f_index.01.L DEF-f_index.02.L DEF-f_index.03.L, \
             middle DEF-f_middle.01.L DEF-f_middle.02.L DEF-f_middle.03.L, \
             ring DEF-f_ring.01.L DEF-f_ring.02.L DEF-f_ring.03.L, \
             pinky DEF-f_pinky.01.L DEF-f_pinky.02.L DEF-f_pinky.03.L; ",
            "right fingers thumb DEF-thumb.01.R DEF-thumb.02.R DEF-thumb.03.R, \
             index DEF-f_index.01.R DEF-f_index.02.R DEF-f_index.03.R, \
             middle DEF-f_middle.01.R DEF-f_middle.02.R DEF-f_middle.03.R, \
             ring DEF-f_ring.01.R DEF-f_ring.02.R DEF-f_ring.03.R, \
             pinky DEF-f_pinky.01.R DEF-f_pinky.02.R DEF-f_pinky.03.R; ",
            "feet DEF-foot.L DEF-toe.L DEF-foot.R DEF-toe.R",
        ],
        &[],
        "y (sure: the figure spreads 161 along y and 20.0 along z over 2 frames)",
    ),
    (
        // Carpals are no finger bone; a metacarpal named for its finger (`lPinky0`) is no
        // phalanx; a fingertip marker counted on from 1 (`lRing4`) is none either.
        "tests/body/daz_carpal.bvh",
        &[
            "from names; ",
            "hips hip; ",
            "spine abdomen chest; ",
            "neck neck; ",
            "head head; ",
            "left arm lCollar > lShldr > lForeArm > lHand; ",
            "left leg lThigh > lShin > lFoot > lToe; ",
            "right arm rCollar > rShldr > rForeArm > rHand; ",
            "right leg rThigh > rShin > rFoot > rToe; ",
            "left fingers thumb lThumb1 lThumb2 lThumb3, index lIndex1 lIndex2 lIndex3, \
             middle lMid1 lMid2 lMid3, ring lRing1 lRing2 lRing3, pinky lPinky1 lPinky2 lPinky3; ",
            "right fingers thumb rThumb1 rThumb2 rThumb3, index rIndex1 rIndex2 rIndex3, \
             middle rMid1 rMid2 rMid3, ring rRing1 rRing2 rRing3, pinky rPinky1 rPinky2 rPinky3; ",
            "feet lFoot lToe rFoot rToe",
        ],
        &[],
        "y (sure: the figure spreads 163 along y and 20.0 along z over 2 frames)",
    ),
    (
        // The ball of the foot as the toe.
        "tests/body/forefoot.bvh",
        &[
            "from names; ",
            "hips Hips; ",
            "spine Spine Spine1; ",
            "neck Neck; ",
            "head Head; ",
            "left arm LeftShoulder > LeftArm > LeftForeArm > LeftHand; ",
            "left leg LeftUpLeg > LeftLeg > LeftFoot > LeftForeFoot; ",
            "right arm RightShoulder > RightArm > RightForeArm > RightHand; ",
            "right leg RightUpLeg > RightLeg > RightFoot > RightForeFoot; ",
            "feet LeftFoot LeftForeFoot RightFoot RightForeFoot",
        ],
        &[],
        "y (sure: the figure spreads 163 along y and 16.0 along z over 2 frames)",
    ),
    (
        // A face hung from the neck is the head.
        "tests/body/face_under_neck.bvh",
        &[
            "from names; ",
            "hips Hips; ",
            "spine Spine Spine1; ",
            "neck Neck; ",
            "head Face; ",
            "left arm LeftShoulder > LeftArm > LeftForeArm > LeftHand; ",
            "left leg LeftUpLeg > LeftLeg > LeftFoot > LeftToe; ",
            "right arm RightShoulder > RightArm > RightForeArm > RightHand; ",
            "right leg RightUpLeg > RightLeg > RightFoot > RightToe; ",
            "feet LeftFoot LeftToe RightFoot RightToe",
        ],
        &[],
        "y (sure: the figure spreads 163 along y and 16.0 along z over 2 frames)",
    ),
    (
        // Names on the wrong sides: the geometry wins, and says so.
        "tests/body/sides_swapped.bvh",
        &[
            "from names; ",
            "hips Hips; ",
            "spine Spine Spine1; ",
            "neck Neck; ",
            "head Head; ",
            "left arm RightShoulder > RightArm > RightForeArm > RightHand; ",
            "left leg RightUpLeg > RightLeg > RightFoot > RightToe; ",
            "right arm LeftShoulder > LeftArm > LeftForeArm > LeftHand; ",
            "right leg LeftUpLeg > LeftLeg > LeftFoot > LeftToe; ",
            "feet LeftFoot LeftToe RightFoot RightToe",
        ],
        &[
            "sides from geometry: the arm and leg named left lie on the body's right (by its \
           toes' facing and its hips' up): sides read from where they lie, not from the names",
        ],
        "y (sure: the figure spreads 163 along y and 16.0 along z over 2 frames)",
    ),
    (
        // No side in any name, facing -z: the body's left is at -x (`Bone.02x`).
        "tests/body/no_side_names.bvh",
        &[
            "from the tree; ",
            "hips Bone; ",
            "spine Bone.001 Bone.002; ",
            "neck Bone.003; ",
            "head Bone.004; ",
            "left arm Bone.020 > Bone.021 > Bone.022 > Bone.023; ",
            "left leg Bone.024 > Bone.025 > Bone.026 > Bone.027; ",
            "right arm Bone.010 > Bone.011 > Bone.012 > Bone.013; ",
            "right leg Bone.014 > Bone.015 > Bone.016 > Bone.017; ",
            "feet Bone.016 Bone.017 Bone.026 Bone.027",
        ],
        &[],
        "y (sure: the figure spreads 163 along y and 16.0 along z over 2 frames)",
    ),
    (
        // A hand alone: no hips, and no up guessed from a body it does not have.
        "tests/body/hand_alone.bvh",
        &[
            "from names; ",
            "hips none; ",
            "spine none; ",
            "neck none; ",
            "head none; ",
            "left arm none > none > none > lHand; ",
            "left leg none > none > none > none; ",
            "right arm none > none > none > none; ",
            "right leg none > none > none > none; ",
            "left fingers thumb lThumb1 lThumb2 lThumb3, index lIndex1 lIndex2 lIndex3, \
             middle lMid1 lMid2 lMid3, ring lRing1 lRing2 lRing3, pinky lPinky1 lPinky2 lPinky3; ",
            "feet none",
        ],
        &["no legs: a hand or part of a body; its up axis is not guessed from a body"],
        "y (unsure: no legs, a hand or part of a body: no body to guess it from, the file's own y)",
    ),
    (
        // A crab: eight legs, and its flat body stood on no axis of its own.
        "tests/body/crab.bvh",
        &[
            "from names; ",
            "hips Body; ",
            "spine none; ",
            "neck none; ",
            "head none; ",
            "left arm none > none > none > none; ",
            "left leg leg1.L > none > none > none; ",
            "right arm none > none > none > none; ",
            "right leg leg1.R > none > none > none; ",
            "feet none",
        ],
        &["eight legs: not a two-legged body; its up axis is not guessed from a body"],
        "y (unsure: eight legs, not a two-legged body: no body to guess it from, the file's own y)",
    ),
];

#[test]
fn bodies_are_read_from_geometry_where_names_mislead_or_say_nothing() {
    for (path, parts, doubts, up) in CLASSES {
        let take = Take::open(path).unwrap();
        let body = Body::of(&take.skeleton);
        assert_eq!(body.summary(&take.skeleton), parts.concat(), "{path}");
        let said: Vec<String> = body
            .doubts(&take.skeleton, &take.motion, OffsetMode::Replace)
            .iter()
            .map(ToString::to_string)
            .collect();
        assert_eq!(said, *doubts, "{path}");
        assert_eq!(take.stance(OffsetMode::Replace).up_text(), *up, "{path}");
        // `info` says the same: the body line, each doubt as a warning, the up axis.
        let out = bvhview_command().args(["info", path]).output().unwrap();
        assert!(out.status.success(), "{path}: {out:?}");
        let text = String::from_utf8(out.stdout).unwrap();
        let line = |key: &str| {
            text.lines()
                .find_map(|l| l.strip_prefix(key).map(str::trim))
                .unwrap_or_else(|| panic!("{path}: no {key} in {text}"))
                .to_string()
        };
        assert_eq!(line("body:"), parts.concat(), "{path}");
        // An unsure guess names the option that says it.
        let named = if up.contains("(unsure") {
            "; --up says it"
        } else {
            ""
        };
        assert_eq!(line("up axis:"), format!("{up}{named}"), "{path}");
        for doubt in *doubts {
            assert!(
                text.contains(&format!("  - body: {doubt}\n")),
                "{path}: {text}"
            );
        }
    }
}

/// Names that contradict where the limbs lie lose: every family's sample, mirrored in its names
/// only (each name given its other side's, nothing moved), reads with the same joints in the
/// same roles as the sample itself, whose names agree with the geometry and change nothing;
/// the disagreement is said.
#[test]
fn sides_follow_where_the_limbs_lie_when_the_names_say_the_other() {
    let mut checked = 0;
    for (path, _) in READINGS
        .iter()
        .filter(|(p, _)| p.starts_with("tests/body/"))
    {
        let original = Take::open(path).unwrap();
        let read = Body::of(&original.skeleton);
        assert_eq!(read.sides_by_geometry, None, "{path}");
        let mut mirrored = original.skeleton.clone();
        for joint in &mut mirrored.joints {
            if let Some(name) = bvhview::model::body::mirrored_name(&joint.name) {
                joint.name = name;
            }
        }
        let body = Body::of(&mirrored);
        assert_eq!(body.limbs, read.limbs, "{path}");
        assert_eq!(body.fingers, read.fingers, "{path}");
        assert!(
            body.sides_by_geometry.as_deref().is_some_and(
                |why| why.starts_with("the arm and leg named left lie on the body's right")
            ),
            "{path}: {:?}",
            body.sides_by_geometry
        );
        checked += 1;
    }
    assert_eq!(checked, 15);
}

/// A crab onto a person is refused as any body that does not stand on two legs is, and a hand
/// alone has no legs to refuse it by.
#[test]
fn a_crab_onto_a_person_is_refused_unless_insisted() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("crab_on_smpl.bvh");
    let refused = bvhview_command()
        .args(["retarget", "tests/body/crab.bvh", "--onto", "smpl22", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(2), "{refused:?}");
    assert_eq!(
        String::from_utf8(refused.stderr).unwrap(),
        "bvhview: tests/body/crab.bvh: not a two-legged body (it has 8 legs), and smpl22 is \
         one: its limbs would be carried over as a person's; `--any-body` retargets it anyway\n"
    );
    assert!(!out.exists());
}
