//! Edits that make a new take: the crate's `edit` results wrapped as a `Motion`, and
//! `Motion.from_arrays` (a take built from arrays on a template's skeleton).

use crate::*;

impl Motion {
    /// A new take from this one's edit: the same path, offset mode and loader warnings;
    /// `same_lengths`: whether units an ASF stated still hold.
    pub(crate) fn edited(
        &self,
        skeleton: bvhview::Skeleton,
        motion: bvhview::Motion,
        same_lengths: bool,
    ) -> Motion {
        Motion {
            loaded: self.loaded.edited(skeleton, motion, same_lengths),
            item: Item {
                path: self.item.path.clone(),
                motion: self.item.motion.clone(),
            },
            offset_mode: self.offset_mode,
        }
    }
}

/// `Motion.from_arrays`: a take built from arrays on `template`'s skeleton.
pub(crate) fn from_arrays(
    py: Python<'_>,
    template: &Motion,
    rotations: numpy::PyArrayLikeDyn<'_, f32, numpy::AllowTypeChange>,
    root_translations: Option<numpy::PyArrayLike2<'_, f32, numpy::AllowTypeChange>>,
    fps: Option<f64>,
    kind: Option<&str>,
) -> PyResult<Motion> {
    let skeleton = &template.loaded.skeleton;
    let joints = skeleton.joints.len();
    let shape = rotations.shape().to_vec();
    let kind = match (kind, &shape[..]) {
        (Some(text), _) => pose::RotationKind::parse(text).ok_or_else(|| {
            PyValueError::new_err(format!(
                "kind={text:?}: expected {}",
                pose::RotationKind::NAMES
            ))
        })?,
        (None, [_, _, 4]) => pose::RotationKind::Quat,
        (None, [_, _, 3, 3]) => pose::RotationKind::Matrix,
        (None, [_, _, 6]) => pose::RotationKind::SixD,
        (None, [_, _, 3]) => pose::RotationKind::Euler,
        (None, _) => {
            return Err(PyValueError::new_err(format!(
                "rotations of shape {shape:?}: expected frames x joints x 4, 3x3, 6 or 3"
            )));
        }
    };
    let per_joint = kind.width();
    if shape.len() < 2 || shape[1] != joints || shape[2..].iter().product::<usize>() != per_joint {
        return Err(PyValueError::new_err(format!(
            "rotations of shape {shape:?}: the template has {joints} joints, and {} takes {per_joint} numbers each",
            kind.name()
        )));
    }
    let frames = shape[0];
    let old = &template.loaded.motion;
    let channels = old.channels;
    let values = frames
        .checked_mul(channels.max(1))
        .filter(|&n| n as u64 <= bvhview::limits::MAX_GENERATED_VALUES)
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "{frames} frames of {channels} values: more than a take holds ({} values at most)",
                bvhview::limits::MAX_GENERATED_VALUES
            ))
        })?;
    // In C order whatever the strides (a slice or a transposed array is fine).
    let rotations: Vec<f32> = rotations.as_array().iter().copied().collect();
    if let Some(at) = rotations.iter().position(|v| !v.is_finite()) {
        let (frame, joint) = (at / per_joint / joints, at / per_joint % joints);
        return Err(PyValueError::new_err(format!(
            "rotations[{frame}, {joint}] is not a finite number"
        )));
    }
    let translations = match &root_translations {
        Some(t) if t.shape() != [frames, 3] => {
            return Err(PyValueError::new_err(format!(
                "root_translations of shape {:?}: expected {frames} x 3",
                t.shape()
            )));
        }
        Some(t) => Some(t.as_array().iter().copied().collect::<Vec<f32>>()),
        None => None,
    };
    if let Some(at) = translations
        .as_ref()
        .and_then(|t| t.iter().position(|v| !v.is_finite()))
    {
        return Err(PyValueError::new_err(format!(
            "root_translations[{}] is not a finite number",
            at / 3
        )));
    }
    // Numbers that stand for no rotation would become NaN angles, which `save` refuses
    // later: refused here, where the caller can see which.
    for frame in 0..frames {
        for (index, joint) in skeleton.joints.iter().enumerate() {
            if !joint.channels.iter().any(|c| c.is_rotation()) {
                continue;
            }
            let numbers = &rotations[(frame * joints + index) * per_joint..][..per_joint];
            if let Some(problem) = pose::rotation_numbers_problem(kind, numbers) {
                return Err(PyValueError::new_err(format!(
                    "rotations[{frame}, {index}] ({}): {problem}",
                    joint.name
                )));
            }
        }
    }
    // The rates `convert --fps` takes: a Motion made at another could not be saved.
    let frame_time = match fps {
        Some(fps) if bvhview::limits::fps(fps, false).is_ok() => 1.0 / fps,
        Some(fps) => {
            return Err(PyValueError::new_err(format!(
                "fps={}: expected frames per second from {} to {}",
                bvhview::limits::show(fps),
                bvhview::limits::show(bvhview::limits::MIN_FPS),
                bvhview::limits::show(bvhview::limits::MAX_FPS)
            )));
        }
        None => template.loaded.motion.frame_time,
    };
    let root = skeleton.roots().next();
    let mode = template.offset_mode;
    let build = || -> Vec<f32> {
        let mut data = Vec::with_capacity(values);
        for frame in 0..frames {
            let start = data.len();
            // Position channels the arrays do not give: the template's.
            if old.frame_count() > 0 {
                data.extend_from_slice(old.frame(frame.min(old.frame_count() - 1)));
            } else {
                for joint in &skeleton.joints {
                    data.extend(
                        joint
                            .channels
                            .iter()
                            .map(|c| match (c.is_position(), mode) {
                                (true, OffsetMode::Replace) => joint.offset[c.axis()],
                                _ => 0.0,
                            }),
                    );
                }
            }
            let row = &mut data[start..];
            for (index, joint) in skeleton.joints.iter().enumerate() {
                let numbers = &rotations[(frame * joints + index) * per_joint..][..per_joint];
                let values =
                    &mut row[joint.first_channel..joint.first_channel + joint.channels.len()];
                if Some(index) == root
                    && let Some(t) = &translations
                {
                    for (channel, value) in joint.channels.iter().zip(values.iter_mut()) {
                        if channel.is_position() {
                            let wanted = t[frame * 3 + channel.axis()];
                            *value = match mode {
                                OffsetMode::Replace => wanted,
                                OffsetMode::Add => wanted - joint.offset[channel.axis()],
                            };
                        }
                    }
                }
                let angles = bvhview::edit::channel_angles(joint, kind, numbers);
                let mut angles = angles.into_iter();
                for (channel, value) in joint.channels.iter().zip(values.iter_mut()) {
                    if channel.is_rotation()
                        && let Some(angle) = angles.next()
                    {
                        *value = angle;
                    }
                }
            }
        }
        data
    };
    let data = py.detach(build);
    let motion = bvhview::Motion::new(frame_time, channels, frames, data);
    let mut take = template.edited(skeleton.clone(), motion, true);
    take.loaded.warnings.clear();
    Ok(take)
}
