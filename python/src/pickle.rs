//! Pickling: a take travels whole (skeleton and values), for multiprocessing, Dask and Ray.

use crate::common::{Keywords, guard, offset_mode_name, parse_offset_mode};
use crate::loaded::Item;
use crate::loaded::Motion;
use bvhview::take::{self, Take};
use glam::Vec3;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// A joint as pickled: name, parent (-1 for a root), OFFSET, channel names, End Site or not,
/// its fixed axis (an ASF bone's, as x, y, z, w) if any.
pub(crate) type JointState = (String, i64, [f32; 3], Vec<String>, bool, Option<[f32; 4]>);

/// A take as pickled: a format number, path, AMC path, offset mode, warnings, whether the
/// skeleton is an ASF's, the units stated (metres per unit, and whether the caller gave them),
/// the joints, the Frame Time, the values per frame, the values (float32, little-endian
/// bytes), and the up axis the caller gave ("y", "z" or none) with the SMPL-family body an
/// AMASS file said.
pub(crate) type State = (
    u32,
    String,
    Option<String>,
    String,
    Vec<String>,
    bool,
    Option<(f32, bool)>,
    Vec<JointState>,
    f64,
    usize,
    Vec<u8>,
    (Option<String>, Option<BodyState>),
);

/// An AMASS file's body as pickled: the model type (`smpl`, `smplh`, `smplx`), betas, gender,
/// and the model's rest pelvis when a model file gave the joints.
pub(crate) type BodyState = (String, Vec<f64>, Option<String>, Option<[f64; 3]>);

/// The version of `State` this module writes and reads.
pub(crate) const STATE_FORMAT: u32 = 3;

impl Motion {
    pub(crate) fn state(&self) -> State {
        let skeleton = &self.loaded.skeleton;
        let joints = skeleton
            .joints
            .iter()
            .map(|j| {
                (
                    j.name.clone(),
                    j.parent.map_or(-1, |p| p as i64),
                    j.offset.to_array(),
                    j.channels.iter().map(|c| c.name().to_string()).collect(),
                    j.end_site,
                    j.axis.map(|q| q.to_array()),
                )
            })
            .collect();
        let motion = &self.loaded.motion;
        (
            STATE_FORMAT,
            self.item.path.display().to_string(),
            self.item.motion.as_ref().map(|p| p.display().to_string()),
            offset_mode_name(self.offset_mode).to_string(),
            // As Python says them: a pickle holds text, not the arguments a warning names.
            self.loaded
                .warnings
                .iter()
                .map(|warning| warning.spelled(&Keywords))
                .collect(),
            skeleton.source == bvhview::model::skeleton::Source::Acclaim,
            self.loaded
                .stated_units
                .map(|units| (units.metres, self.loaded.units_given)),
            joints,
            motion.frame_time,
            motion.channels,
            motion.data.iter().flat_map(|v| v.to_le_bytes()).collect(),
            (
                self.loaded.stated_up.map(|up| {
                    match up {
                        bvhview::model::pose::Up::Y => "y",
                        bvhview::model::pose::Up::Z => "z",
                    }
                    .to_string()
                }),
                self.loaded.body.as_ref().map(|body| {
                    (
                        body.model.label().replace('-', "").to_ascii_lowercase(),
                        body.betas.clone(),
                        body.gender.clone(),
                        body.rest_pelvis,
                    )
                }),
            ),
        )
    }
}

/// A take from its pickled state (see `Motion.__reduce__`).
#[pyfunction]
pub(crate) fn _from_state(state: State) -> PyResult<Motion> {
    guard("_from_state", || {
        let (
            format,
            path,
            motion_path,
            mode,
            warnings,
            acclaim,
            stated_units,
            joints,
            frame_time,
            channels,
            data,
            (stated_up, body),
        ) = state;
        let bad =
            |what: &str| PyValueError::new_err(format!("not a pickled bvhview.Motion: {what}"));
        if format != STATE_FORMAT {
            return Err(bad(&format!(
                "format {format}, this bvhview reads {STATE_FORMAT}"
            )));
        }
        if stated_units.is_some_and(|(metres, _)| !(metres.is_finite() && metres > 0.0)) {
            return Err(bad("units that are not a length above 0"));
        }
        // Not in the state: a glTF states its axes always, an FBX unless it said it did not.
        let extension = std::path::Path::new(&path)
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        let y_up_stated = match extension.as_deref() {
            Some("glb" | "gltf") => true,
            Some("fbx") => !warnings.iter().any(|w| w.contains("states no axes")),
            _ => false,
        };
        let mut skeleton = bvhview::Skeleton {
            joints: Vec::with_capacity(joints.len()),
            source: if acclaim {
                bvhview::model::skeleton::Source::Acclaim
            } else {
                bvhview::model::skeleton::Source::Bvh
            },
            y_up_stated,
        };
        if !bvhview::limits::frame_time_in_file(frame_time) {
            return Err(bad(&format!("a frame time of {frame_time} s")));
        }
        let mut first_channel = 0;
        for (index, (name, parent, offset, names, end_site, axis)) in joints.into_iter().enumerate()
        {
            // Pre-order: a joint's parent is the joint before it or one of that joint's ancestors.
            let parent = match parent {
                -1 => None,
                p if p >= 0 && (p as usize) < index => {
                    let p = p as usize;
                    let mut line = Some(index - 1);
                    while let Some(at) = line.filter(|&at| at != p) {
                        line = skeleton.joints[at].parent;
                    }
                    if line.is_none() {
                        return Err(bad("joints out of pre-order"));
                    }
                    Some(p)
                }
                _ => return Err(bad("a parent after its child")),
            };
            if let Some(parent) = parent
                && skeleton.joints[parent].end_site
            {
                return Err(bad("an End Site with children"));
            }
            if end_site && !names.is_empty() {
                return Err(bad("an End Site with channels"));
            }
            // Written so that NaN fails: a NaN length is not within 1e-3 of 1.
            let unit = |q: [f32; 4]| {
                q.iter().all(|v| v.is_finite())
                    && (glam::Quat::from_array(q).length() - 1.0).abs() <= 1e-3
            };
            if !offset.iter().all(|v| v.is_finite()) || axis.is_some_and(|q| !unit(q)) {
                return Err(bad("an OFFSET or an axis that is not a finite rotation"));
            }
            let mut joint = bvhview::Joint::new(name, parent);
            joint.offset = Vec3::from_array(offset);
            joint.channels = names
                .iter()
                .map(|n| bvhview::Channel::parse(n).ok_or_else(|| bad("a channel name")))
                .collect::<PyResult<_>>()?;
            joint.rotation_order = bvhview::RotationOrder::get_flags(&joint.channels);
            joint.first_channel = first_channel;
            first_channel += joint.channels.len();
            joint.end_site = end_site;
            joint.axis = axis.map(glam::Quat::from_array);
            if let Some(parent) = parent {
                skeleton.joints[parent].children.push(index);
            }
            skeleton.joints.push(joint);
        }
        if first_channel != channels
            || data.len() % 4 != 0
            || (channels == 0 && !data.is_empty())
            || (channels > 0 && data.len() / 4 % channels != 0)
        {
            return Err(bad("values that do not fit the channels"));
        }
        let values: Vec<f32> = data
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        if values.iter().any(|v| !v.is_finite()) {
            return Err(bad("a value that is not a finite number"));
        }
        let frames = values.len().checked_div(channels).unwrap_or(0);
        let loaded = Take {
            warnings: warnings.into_iter().map(bvhview::Message::from).collect(),
            stated_units: stated_units
                .map(|(metres, _)| bvhview::model::stance::Units::of_metres(metres)),
            units_given: stated_units.is_some_and(|(_, given)| given),
            // A pickle holds y or z: a take given another was turned to y as it was read.
            stated_up: stated_up
                .as_deref()
                .map(crate::common::parse_up)
                .transpose()?
                .and_then(bvhview::model::pose::UpAxis::standing),
            format: take::Format::from_path(Path::new(&path)),
            body: match body {
                Some((model, betas, gender, rest_pelvis)) => Some(bvhview::smpl::Body {
                    model: bvhview::smpl::ModelType::named(&model)
                        .ok_or_else(|| bad("a body of no SMPL model type"))?,
                    betas,
                    gender,
                    rest_pelvis,
                }),
                None => None,
            },
            ..Take::new(
                skeleton,
                bvhview::Motion::new(frame_time, channels, frames, values),
                path.clone(),
            )
        };
        Ok(Motion {
            loaded,
            item: Item {
                path: PathBuf::from(path),
                motion: motion_path.map(PathBuf::from),
            },
            offset_mode: parse_offset_mode(&mode)?,
            check: None,
        })
    })
}
