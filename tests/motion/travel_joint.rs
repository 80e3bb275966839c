//! The travel joint is the hips or a joint above them, never a limb: a file that gives
//! every joint position channels (Bandai, Perception Neuron, Rigify) had its travel read from
//! whichever limb strayed farthest.

use crate::common;

use bvhview::Take;
use bvhview::model::body::travel_joint_of_take;
use bvhview::model::pose::OffsetMode;

/// Every joint with six channels; over two frames the hips move 10 units and the left hand
/// (by its own position channels) 80.
const EVERY_JOINT_TRANSLATED: &str = "HIERARCHY
ROOT Hips
{
  OFFSET 0 100 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT LeftUpLeg
  {
    OFFSET 10 0 0
    CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 -90 0
    }
  }
  JOINT RightUpLeg
  {
    OFFSET -10 0 0
    CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 -90 0
    }
  }
  JOINT Spine
  {
    OFFSET 0 10 0
    CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
    JOINT LeftHand
    {
      OFFSET 40 30 0
      CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
      End Site
      {
        OFFSET 10 0 0
      }
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.5
0 100 0 0 0 0 10 0 0 0 0 0 -10 0 0 0 0 0 0 10 0 0 0 0 40 30 0 0 0 0
10 100 0 0 0 0 10 0 0 0 0 0 -10 0 0 0 0 0 0 10 0 0 0 0 120 30 0 0 0 0
";

#[test]
fn the_travel_is_the_hips_not_the_limb_that_strays_farthest() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("every_joint_translated.bvh");
    std::fs::write(&path, EVERY_JOINT_TRANSLATED).unwrap();
    let take = Take::open(&path).unwrap();
    let travel = travel_joint_of_take(&take.skeleton, &take.motion, OffsetMode::Replace);
    assert_eq!(take.skeleton.joints[travel].name, "Hips");
    let info = crate::common::bvhview_command()
        .arg("info")
        .arg(&path)
        .output()
        .unwrap();
    let text = String::from_utf8(info.stdout).unwrap();
    assert!(
        text.lines()
            .any(|l| l.starts_with("travel:           Hips ")),
        "{text}"
    );
}

/// Bandai's takes give every joint position channels; `info` said `Foot_L` (a dance) and
/// `Hand_L` (a wave) before.
#[test]
#[ignore = "reads ../shared/data (the whole corpus); scripts/test.sh runs it when present"]
fn bandai_takes_travel_on_their_hips() {
    for name in [
        "bvh/bandai_dataset-1_dance-short_normal_001.bvh",
        "bvh/bandai_dataset-2_wave-left-hand_active_011.bvh",
    ] {
        let take = Take::open(common::shared_data(name)).unwrap();
        let travel = travel_joint_of_take(&take.skeleton, &take.motion, OffsetMode::Replace);
        assert_eq!(take.skeleton.joints[travel].name, "Hips", "{name}");
    }
}
