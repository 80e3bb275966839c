//! Side names of every naming family in the corpus, by hand.

use super::*;

/// Every name of a rig's list that is not in `centre` marks a side, and its mirrored name
/// is in the list and marks the other; the names in `centre` mark none; as many left as
/// right.
fn family(names: &[&str], centre: &[&str]) {
    let (mut left, mut right) = (0, 0);
    for &name in names {
        let guess = name_side(name);
        if centre.contains(&name) {
            assert_eq!(guess, None, "{name} has no side");
            continue;
        }
        let (side, other) = guess.unwrap_or_else(|| panic!("{name} has a side"));
        assert!(
            names.contains(&other.as_str()),
            "{name} → {other}: not in the rig"
        );
        let (back_side, back) = name_side(&other).unwrap();
        assert_eq!(
            (back_side, back.as_str()),
            (side.other(), name),
            "{name} → {other}"
        );
        match side {
            Side::Left => left += 1,
            Side::Right => right += 1,
        }
    }
    assert_eq!(left, right, "{names:?}");
    assert!(left > 0);
}

#[test]
fn side_names_of_cmu_bvh() {
    // cgspeed's conversions of CMU's takes (the repository's assimp_01_01.bvh).
    family(
        &[
            "Hips",
            "LHipJoint",
            "LeftUpLeg",
            "LeftLeg",
            "LeftFoot",
            "LeftToeBase",
            "RHipJoint",
            "RightUpLeg",
            "RightLeg",
            "RightFoot",
            "RightToeBase",
            "LowerBack",
            "Spine",
            "Spine1",
            "Neck",
            "Neck1",
            "Head",
            "LeftShoulder",
            "LeftArm",
            "LeftForeArm",
            "LeftHand",
            "LeftFingerBase",
            "LeftHandIndex1",
            "LThumb",
            "RightShoulder",
            "RightArm",
            "RightForeArm",
            "RightHand",
            "RightFingerBase",
            "RightHandIndex1",
            "RThumb",
        ],
        &[
            "Hips",
            "LowerBack",
            "Spine",
            "Spine1",
            "Neck",
            "Neck1",
            "Head",
        ],
    );
}

#[test]
fn side_names_of_cmu_asf() {
    family(
        &[
            "root",
            "lhipjoint",
            "lfemur",
            "ltibia",
            "lfoot",
            "ltoes",
            "rhipjoint",
            "rfemur",
            "rtibia",
            "rfoot",
            "rtoes",
            "lowerback",
            "upperback",
            "thorax",
            "lowerneck",
            "upperneck",
            "head",
            "lclavicle",
            "lhumerus",
            "lradius",
            "lwrist",
            "lhand",
            "lfingers",
            "lthumb",
            "rclavicle",
            "rhumerus",
            "rradius",
            "rwrist",
            "rhand",
            "rfingers",
            "rthumb",
        ],
        &[
            "root",
            "lowerback",
            "upperback",
            "thorax",
            "lowerneck",
            "upperneck",
            "head",
        ],
    );
}

#[test]
fn side_names_of_cgspeed() {
    family(
        &[
            "hips",
            "lhipjoint",
            "lhip",
            "lknee",
            "lankle",
            "lfoot",
            "ltoe",
            "rhipjoint",
            "rhip",
            "rknee",
            "rankle",
            "rfoot",
            "rtoe",
            "lowerback",
            "upperback",
            "chest",
            "neck",
            "head",
            "lcollar",
            "lshoulder",
            "lelbow",
            "lwrist",
            "lhand",
            "rcollar",
            "rshoulder",
            "relbow",
            "rwrist",
            "rhand",
        ],
        &["hips", "lowerback", "upperback", "chest", "neck", "head"],
    );
    // cgspeed's Daz-friendly release.
    family(
        &[
            "hip", "abdomen", "chest", "neck", "head", "leftEye", "rightEye", "rCollar", "rShldr",
            "rForeArm", "rHand", "rThumb1", "rIndex1", "rMid1", "rRing1", "rPinky1", "lCollar",
            "lShldr", "lForeArm", "lHand", "lThumb1", "lIndex1", "lMid1", "lRing1", "lPinky1",
            "rButtock", "rThigh", "rShin", "rFoot", "lButtock", "lThigh", "lShin", "lFoot",
        ],
        &["hip", "abdomen", "chest", "neck", "head"],
    );
}

#[test]
fn side_names_of_mixamo() {
    let names: Vec<String> = [
        "Hips",
        "Spine",
        "Spine1",
        "Spine2",
        "Neck",
        "Head",
        "HeadTop_End",
        "LeftShoulder",
        "LeftArm",
        "LeftForeArm",
        "LeftHand",
        "LeftHandThumb1",
        "LeftHandIndex1",
        "LeftHandIndex4",
        "LeftUpLeg",
        "LeftLeg",
        "LeftFoot",
        "LeftToeBase",
        "LeftToe_End",
        "RightShoulder",
        "RightArm",
        "RightForeArm",
        "RightHand",
        "RightHandThumb1",
        "RightHandIndex1",
        "RightHandIndex4",
        "RightUpLeg",
        "RightLeg",
        "RightFoot",
        "RightToeBase",
        "RightToe_End",
    ]
    .iter()
    .map(|n| format!("mixamorig:{n}"))
    .collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    family(
        &names,
        &[
            "mixamorig:Hips",
            "mixamorig:Spine",
            "mixamorig:Spine1",
            "mixamorig:Spine2",
            "mixamorig:Neck",
            "mixamorig:Head",
            "mixamorig:HeadTop_End",
        ],
    );
    assert_eq!(
        mirrored_name("mixamorig1:LeftHand").as_deref(),
        Some("mixamorig1:RightHand")
    );
    assert_eq!(
        mirrored_name("Beta:RightUpLeg").as_deref(),
        Some("Beta:LeftUpLeg")
    );
}

#[test]
fn side_names_of_lafan1() {
    family(
        &[
            "Hips",
            "LeftUpLeg",
            "LeftLeg",
            "LeftFoot",
            "LeftToe",
            "RightUpLeg",
            "RightLeg",
            "RightFoot",
            "RightToe",
            "Spine",
            "Spine1",
            "Spine2",
            "Neck",
            "Head",
            "LeftShoulder",
            "LeftArm",
            "LeftForeArm",
            "LeftHand",
            "RightShoulder",
            "RightArm",
            "RightForeArm",
            "RightHand",
        ],
        &["Hips", "Spine", "Spine1", "Spine2", "Neck", "Head"],
    );
}

#[test]
fn side_names_of_bandai() {
    family(
        &[
            "joint_Root",
            "Hips",
            "Spine",
            "Chest",
            "Neck",
            "Head",
            "Shoulder_L",
            "UpperArm_L",
            "LowerArm_L",
            "Hand_L",
            "Shoulder_R",
            "UpperArm_R",
            "LowerArm_R",
            "Hand_R",
            "UpperLeg_L",
            "LowerLeg_L",
            "Foot_L",
            "Toes_L",
            "UpperLeg_R",
            "LowerLeg_R",
            "Foot_R",
            "Toes_R",
        ],
        &["joint_Root", "Hips", "Spine", "Chest", "Neck", "Head"],
    );
}

#[test]
fn side_names_of_xsens() {
    // L5, L3, T12 and T8 are vertebrae, not sides.
    family(
        &[
            "Pelvis",
            "L5",
            "L3",
            "T12",
            "T8",
            "Neck",
            "Head",
            "RightShoulder",
            "RightUpperArm",
            "RightForeArm",
            "RightHand",
            "LeftShoulder",
            "LeftUpperArm",
            "LeftForeArm",
            "LeftHand",
            "RightUpperLeg",
            "RightLowerLeg",
            "RightFoot",
            "RightToe",
            "LeftUpperLeg",
            "LeftLowerLeg",
            "LeftFoot",
            "LeftToe",
        ],
        &["Pelvis", "L5", "L3", "T12", "T8", "Neck", "Head"],
    );
}

#[test]
fn side_names_of_daz_poser_and_second_life() {
    // Daz Genesis.
    family(
        &[
            "hip",
            "pelvis",
            "lThighBend",
            "lThighTwist",
            "lShin",
            "lFoot",
            "lMetatarsals",
            "lToe",
            "rThighBend",
            "rThighTwist",
            "rShin",
            "rFoot",
            "rMetatarsals",
            "rToe",
            "abdomenLower",
            "abdomenUpper",
            "chestLower",
            "chestUpper",
            "lPectoral",
            "rPectoral",
            "lCollar",
            "lShldrBend",
            "lShldrTwist",
            "lForearmBend",
            "lHand",
            "lThumb1",
            "rCollar",
            "rShldrBend",
            "rShldrTwist",
            "rForearmBend",
            "rHand",
            "rThumb1",
            "neckLower",
            "neckUpper",
            "head",
            "lEye",
            "rEye",
            "lowerJaw",
            "upperJaw",
            "lowerFaceRig",
        ],
        &[
            "hip",
            "pelvis",
            "abdomenLower",
            "abdomenUpper",
            "chestLower",
            "chestUpper",
            "neckLower",
            "neckUpper",
            "head",
            "lowerJaw",
            "upperJaw",
            "lowerFaceRig",
        ],
    );
    // Second Life (the repository's opencollar takes), Bento included.
    family(
        &[
            "hip",
            "abdomen",
            "chest",
            "neck",
            "head",
            "lCollar",
            "lShldr",
            "lForeArm",
            "lHand",
            "rCollar",
            "rShldr",
            "rForeArm",
            "rHand",
            "lThigh",
            "lShin",
            "lFoot",
            "rThigh",
            "rShin",
            "rFoot",
            "mPelvis",
            "mTorso",
            "mChest",
            "mNeck",
            "mHead",
            "mHipLeft",
            "mKneeLeft",
            "mAnkleLeft",
            "mHipRight",
            "mKneeRight",
            "mAnkleRight",
            "mCollarLeft",
            "mShoulderLeft",
            "mElbowLeft",
            "mWristLeft",
            "mCollarRight",
            "mShoulderRight",
            "mElbowRight",
            "mWristRight",
            "mEyeLeft",
            "mEyeRight",
            "mFaceEar1Left",
            "mFaceEar1Right",
            "mHandThumb1Left",
            "mHandThumb1Right",
            "mFaceNoseCenter",
            "mFaceJaw",
        ],
        &[
            "hip",
            "abdomen",
            "chest",
            "neck",
            "head",
            "mPelvis",
            "mTorso",
            "mChest",
            "mNeck",
            "mHead",
            "mFaceNoseCenter",
            "mFaceJaw",
        ],
    );
}

#[test]
fn side_names_of_rokoko() {
    family(
        &[
            "Hips",
            "Spine1",
            "Spine2",
            "Spine3",
            "Spine4",
            "Neck",
            "Head",
            "LeftShoulder",
            "LeftArm",
            "LeftForeArm",
            "LeftHand",
            "LeftFinger1Metacarpal",
            "LeftThigh",
            "LeftShin",
            "LeftFoot",
            "LeftToe",
            "LeftToeEnd",
            "RightShoulder",
            "RightArm",
            "RightForeArm",
            "RightHand",
            "RightFinger1Metacarpal",
            "RightThigh",
            "RightShin",
            "RightFoot",
            "RightToe",
            "RightToeEnd",
            "LeftInHandIndex",
            "RightInHandIndex",
        ],
        &[
            "Hips", "Spine1", "Spine2", "Spine3", "Spine4", "Neck", "Head",
        ],
    );
}

#[test]
fn side_names_of_smpl() {
    family(
        &[
            "pelvis",
            "left_hip",
            "right_hip",
            "spine1",
            "left_knee",
            "right_knee",
            "spine2",
            "left_ankle",
            "right_ankle",
            "spine3",
            "left_foot",
            "right_foot",
            "neck",
            "left_collar",
            "right_collar",
            "head",
            "left_shoulder",
            "right_shoulder",
            "left_elbow",
            "right_elbow",
            "left_wrist",
            "right_wrist",
            "left_hand",
            "right_hand",
        ],
        &["pelvis", "spine1", "spine2", "spine3", "neck", "head"],
    );
    family(
        &[
            "Pelvis",
            "L_Hip",
            "R_Hip",
            "Spine1",
            "L_Knee",
            "R_Knee",
            "Spine2",
            "L_Ankle",
            "R_Ankle",
            "Spine3",
            "L_Foot",
            "R_Foot",
            "Neck",
            "L_Collar",
            "R_Collar",
            "Head",
            "L_Shoulder",
            "R_Shoulder",
            "L_Elbow",
            "R_Elbow",
            "L_Wrist",
            "R_Wrist",
            "L_Hand",
            "R_Hand",
        ],
        &["Pelvis", "Spine1", "Spine2", "Spine3", "Neck", "Head"],
    );
}

#[test]
fn side_names_of_makehuman_blender_unreal_and_3ds_max() {
    family(
        &[
            "root",
            "spine05",
            "pelvis.L",
            "pelvis.R",
            "upperleg01.L",
            "upperleg01.R",
            "toe1-1.L",
            "toe1-1.R",
            "__Eye_L",
            "__Eye_R",
            "Clavicle_L",
            "Clavicle_R",
            "DEF-thigh.L",
            "DEF-thigh.R",
            "thigh.L.001",
            "thigh.R.001",
            "thigh_l",
            "thigh_r",
            "calf_l",
            "calf_r",
            "spine_01",
            "neck_01",
            "Bip01 L Thigh",
            "Bip01 R Thigh",
            "Bip01 Pelvis",
            "Bip01 Spine",
            "LEFT_ARM",
            "RIGHT_ARM",
            "lefthand",
            "righthand",
        ],
        &[
            "root",
            "spine05",
            "spine_01",
            "neck_01",
            "Bip01 Pelvis",
            "Bip01 Spine",
        ],
    );
}

#[test]
fn names_without_a_side() {
    for name in [
        "Hips",
        "Spine",
        "Head",
        "Neck",
        "lowerback",
        "upperback",
        "LowerBack",
        "Chest",
        "L5",
        "T8",
        "rotation",
        "Root",
        "ROOT",
        "RootNode",
        "Leftover",
        "upright",
        "Bright",
        "Light",
        "lowerneck",
        "hip",
        "ring",
        "rib",
        "lip",
        "Site",
        "Reference",
        "LOWER",
    ] {
        assert_eq!(name_side(name), None, "{name}");
    }
}
