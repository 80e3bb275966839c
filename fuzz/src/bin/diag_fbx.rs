use bvhview_fuzz::edited_take;
use std::io::Read;
fn main() {
    let mut data = Vec::new();
    std::io::stdin().read_to_end(&mut data).unwrap();
    let Some((_, skeleton, motion)) = edited_take(&data) else { println!("none"); return; };
    let take = bvhview::Take::new(skeleton, motion, "fuzz".to_string());
    let written = take.fbx().unwrap();
    let back = bvhview::OpenOptions::new().open_bytes(&written.bytes, "fuzz.fbx").unwrap();
    let again = back.fbx().unwrap();
    let st = take.stance(take.offset_mode);
    let bs = back.stance(back.offset_mode);
    println!("src units {} {} up {:?} frames {} ft {} joints {}", st.units.name, st.units.metres, st.up, take.motion.frame_count(), take.motion.frame_time, take.skeleton.joints.len());
    println!("back units {:?} {} up {:?} frames {} ft {}", back.stated_units.map(|u| u.name), bs.units.metres, bs.up, back.motion.frame_count(), back.motion.frame_time);
    for (a, b) in take.skeleton.joints.iter().zip(&back.skeleton.joints) {
        if a.name != b.name || a.channels != b.channels || a.end_site != b.end_site { println!("joint {:?} {:?} {:?} {:?} {:?} {:?} end {} {}", a.name, b.name, a.channels, b.channels, a.rotation_order, b.rotation_order, a.end_site, b.end_site); }
    }
    let at = written.bytes.iter().zip(&again.bytes).position(|(a, b)| a != b);
    println!("lens {} {} first diff {:?}", written.bytes.len(), again.bytes.len(), at);
    if let Some(at) = at { let s = at.saturating_sub(60); println!("{:?}\n{:?}", String::from_utf8_lossy(&written.bytes[s..(at+40).min(written.bytes.len())]), String::from_utf8_lossy(&again.bytes[s..(at+40).min(again.bytes.len())])); }
}
