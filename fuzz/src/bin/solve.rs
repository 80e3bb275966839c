//! Any bytes into `solve`'s readers and then `solve` onto the built-in `smpl22`, as `bvhview
//! solve FILE --onto smpl22 --fps 20` does: an input whose first byte is numpy's 0x93 is an
//! `.npy` (frames × joints × 3, or HumanML3D's frames × 263 as `--from humanml3d` reads it),
//! any other the positions CSV. The readers must refuse it or give positions, and `solve` must
//! refuse those or give a take that writes as BVH, never panic or hang.
use bvhview::retarget::Target;
use bvhview::solve::{self, Positions};

fn main() {
    let target = Target::load("smpl22", u64::MAX).expect("the built-in skeleton");
    // What an .npy's joints are called: SMPL's 22 when there are 22 (the CLI's default), else
    // the first of the points `bvhview positions` writes of smpl22 (as `--joints` names them).
    let points: Vec<String> = bvhview::positions::export_points(&target.skeleton)
        .into_iter()
        .map(|(name, _)| name)
        .collect();
    let frame_time = 1.0 / 20.0;
    afl::fuzz!(|data: &[u8]| {
        let positions = if data.first() == Some(&0x93) {
            match solve::read_npy(data, "fuzz.npy") {
                Ok((joints, values)) => {
                    let names = match joints {
                        22 => solve::joint_names("smpl22"),
                        n if n <= points.len() => points[..n].to_vec(),
                        _ => return,
                    };
                    Positions::new(names, values, frame_time)
                }
                Err(_) => match bvhview::humanml3d::read_vectors(data, "fuzz.npy") {
                    Ok(vectors) => match bvhview::humanml3d::recover_from_ric(&vectors) {
                        Ok(values) => {
                            Positions::new(solve::joint_names("smpl22"), values, frame_time)
                        }
                        Err(_) => return,
                    },
                    Err(_) => return,
                },
            }
        } else {
            let Ok(text) = std::str::from_utf8(data) else {
                return;
            };
            match solve::read_csv(text, "fuzz.csv") {
                Ok((names, values)) => Positions::new(names, values, frame_time),
                Err(_) => return,
            }
        };
        let Ok(positions) = positions else {
            return;
        };
        if let Ok((motion, solved)) = solve::solve(&target.skeleton, target.up, &positions, None) {
            assert_eq!(motion.frame_count(), positions.frames());
            let _ = solved.summary(&target.skeleton);
            let _ = solved.off_the_data_line(&target.skeleton);
            let _ = bvhview::bvh::writer::to_string(&target.skeleton, &motion);
        }
    });
}
