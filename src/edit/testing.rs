//! Takes the edits' tests share.

pub(super) fn take(text: &str) -> crate::bvh::Bvh {
    crate::bvh::load_bytes(text.as_bytes(), "t.bvh").unwrap()
}

pub(super) const TWO_FRAMES: &str = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition \
    Zposition Zrotation Xrotation Yrotation\nJOINT Chest\n{\nOFFSET 0 10 0\nCHANNELS 3 \
    Zrotation Xrotation Yrotation\nEnd Site\n{\nOFFSET 0 5 0\n}\n}\n}\nMOTION\nFrames: 3\n\
    Frame Time: 0.5\n0 0 0 0 0 0 0 0 0\n4 2 -2 0 0 0 40 0 0\n8 4 -4 0 0 0 80 0 0\n";
