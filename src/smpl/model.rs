//! The user's own body model file (SMPL, SMPL-H or SMPL-X as an `.npz`) and its forward pass, as
//! the `smplx` package computes it: the shaped rest body `v_template + shapedirs · betas`, its
//! joints `J_regressor · vertices`, the pose blend shapes `posedirs · (R − I)` of every joint but
//! the root, and linear blend skinning by `weights`; `trans` added last.
//!
//! Model files are licensed and never shipped: bvhview reads the user's. Every array is checked
//! against the model type its kinematic tree names (`kintree_table`), and nothing of the file
//! is used before it holds: a pickled array (the sparse `J_regressor` of some conversions) is
//! refused by name, as is a `.pkl` (chumpy's pickles are not read: convert them to `.npz`).

use super::layout::ModelType;
use super::npz::{Npz, numbers};
use crate::io::error::Error;
use glam::{DMat3, DVec3};
use std::path::{Path, PathBuf};

/// Columns of `shapedirs` that are shape in a SMPL-X file of 400 (the expression's follow).
const SMPLX_SHAPE_SPACE: usize = 300;

/// Most vertices a body model may have (SMPL-X has 10,475).
const MAX_VERTICES: usize = 1 << 20;

/// A body model read from the user's file.
///
/// ```no_run
/// use bvhview::smpl::model::BodyModel;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let smplx = BodyModel::open("models/SMPLX_NEUTRAL.npz".as_ref(), None, None, u64::MAX)?;
/// let body = smplx.shaped(&[0.5, -1.0], &[])?;
/// let posed = smplx.forward(&body, &vec![0.0; 165], glam::DVec3::ZERO);
/// assert_eq!(posed.vertices.len(), 10475);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BodyModel {
    /// The model type its kinematic tree names.
    pub model: ModelType,
    /// What messages call it: its path.
    pub name: String,
    /// `female`, `male` or `neutral`, as its file name says, if it says.
    pub gender: Option<String>,
    template: Vec<DVec3>,
    /// `shapedirs` as the file holds it: vertex, axis, component.
    shape_dirs: Vec<f64>,
    shape_dirs_width: usize,
    shape_count: usize,
    expression_start: usize,
    expression_count: usize,
    /// `posedirs`: vertex, axis, pose feature (9 a joint after the root).
    pose_dirs: Vec<f64>,
    /// Each joint's vertices and weights in `J_regressor` (its non-zero entries).
    regressor: Vec<Vec<(u32, f64)>>,
    /// Where each vertex's skinning weights start in `weights` (one more than vertices).
    weight_start: Vec<u32>,
    /// Each vertex's non-zero skinning weights: joint, weight.
    weights: Vec<(u32, f64)>,
    /// Three vertex indices a triangle.
    pub faces: Vec<u32>,
}

/// A body of a given shape in its rest pose: each vertex and joint, metres, the model's Y up.
///
/// ```no_run
/// use bvhview::smpl::model::BodyModel;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let smpl = BodyModel::open("models/SMPL_NEUTRAL.npz".as_ref(), None, None, u64::MAX)?;
/// let tall = smpl.shaped(&[-2.0], &[])?;
/// let pelvis_to_head = tall.joints[15] - tall.joints[0];
/// assert!(pelvis_to_head.y > 0.0); // the model stands along y
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Shaped {
    /// `v_template + shapedirs · (betas, expression)`.
    pub vertices: Vec<DVec3>,
    /// `J_regressor · vertices`.
    pub joints: Vec<DVec3>,
    /// How many of the betas given the model has components for (the rest are not used).
    pub betas_used: usize,
}

/// A posed body: each joint and vertex in the world, `trans` added.
///
/// ```no_run
/// use bvhview::smpl::model::BodyModel;
/// use glam::DVec3;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let smplh = BodyModel::open("models/".as_ref(), Some("female"), None, u64::MAX)?;
/// let body = smplh.shaped(&[0.3; 16], &[])?;
/// let mut pose = vec![0.0; 156];
/// pose[3 * 4] = 1.2; // the left knee bent about x
/// let posed = smplh.forward(&body, &pose, DVec3::new(0.0, 0.0, 0.9));
/// assert_eq!(posed.joints.len(), 52);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Posed {
    /// The joints, in the model type's order.
    pub joints: Vec<DVec3>,
    /// The vertices.
    pub vertices: Vec<DVec3>,
}

impl BodyModel {
    /// Reads a model file (at most `max_size` bytes), or the one in a folder for `gender` (`female`, `male`, `neutral`;
    /// none, or none of that gender there: the neutral one, else the only one) and, where the folder holds several, of the
    /// type `wanted` (by name): `SMPLX_NEUTRAL.npz`, `smplh/male/model.npz` and the like.
    pub fn open(
        path: &Path,
        gender: Option<&str>,
        wanted: Option<ModelType>,
        max_size: u64,
    ) -> Result<BodyModel, Error> {
        let file = if path.is_dir() {
            model_in_folder(path, gender, wanted)?
        } else {
            path.to_path_buf()
        };
        if file
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("pkl"))
        {
            return Err(Error::usage(format!(
                "{}: a pickled model file (.pkl) is not read (pickles run code when loaded); \
                 give its .npz (the SMPL-X site ships them, and `np.savez` of the loaded \
                 arrays makes one)",
                file.display()
            )));
        }
        let bytes = crate::io::whole::read_binary_file(&file, max_size)?;
        let shown = file.display().to_string();
        let mut model = BodyModel::from_bytes(&bytes, &shown)?;
        // The file's own name says it (`SMPLX_FEMALE.npz`), else its folder's (`female/model.npz`),
        // never a folder further up (`/data/female_study/SMPLX_NEUTRAL.npz` is neutral).
        let named = |p: Option<&std::ffi::OsStr>| p.and_then(|n| gender_of(Path::new(n)));
        model.gender =
            named(file.file_name()).or_else(|| named(file.parent().and_then(Path::file_name)));
        Ok(model)
    }

    /// Reads a model from the bytes of its `.npz`, named `shown` in errors.
    pub fn from_bytes(bytes: &[u8], shown: &str) -> Result<BodyModel, Error> {
        let npz = super::npz::read(bytes, shown)?;
        BodyModel::from_npz(npz, shown)
    }

    /// Reads a model from an `.npz`'s arrays.
    pub fn from_npz(mut npz: Npz, shown: &str) -> Result<BodyModel, Error> {
        let refuse = |why: String| Error::decoding(shown, why);
        let need = |key: &str| -> Result<(&[usize], &[f64]), Error> {
            numbers(&npz, key, shown)?.ok_or_else(|| {
                let hint = if npz.get("poses").is_some() || npz.get("trans").is_some() {
                    " (this is a motion file, AMASS's: a body model holds v_template, \
                     shapedirs, posedirs, J_regressor, weights, kintree_table and f)"
                } else {
                    ""
                };
                refuse(format!(
                    "no '{key}' array: not a SMPL-family model file{hint}"
                ))
            })
        };
        let finite = |key: &str, values: &[f64]| match values.iter().position(|v| !v.is_finite()) {
            Some(i) => Err(refuse(format!("'{key}' value {i} is not a finite number"))),
            None => Ok(()),
        };
        let (shape, tree) = need("kintree_table")?;
        let joints = match shape {
            [2, j] => *j,
            _ => {
                return Err(refuse(format!(
                    "'kintree_table' has shape {shape:?}; expected 2 × joints"
                )));
            }
        };
        let model = ModelType::ALL
            .into_iter()
            .find(|m| m.joint_count() == joints)
            .ok_or_else(|| {
                refuse(format!(
                    "its tree has {joints} joints; SMPL has 24, SMPL-H 52, SMPL-X 55"
                ))
            })?;
        let expected = model.parents();
        for (k, want) in expected.iter().enumerate() {
            let parent = tree[k];
            let child = tree[joints + k];
            let said = (parent >= 0.0 && parent < joints as f64).then_some(parent as usize);
            if child != k as f64 || said != *want {
                return Err(refuse(format!(
                    "'kintree_table' column {k} says joint {child} under {parent}; {}'s joint \
                     {k} ({}) is under {}",
                    model.label(),
                    model.joint_names()[k],
                    want.map_or("nothing (the root)".to_string(), |p| p.to_string())
                )));
            }
        }
        let (shape, template) = need("v_template")?;
        let vertices = match shape {
            [v, 3] if *v > 0 && *v <= MAX_VERTICES => *v,
            _ => {
                return Err(refuse(format!(
                    "'v_template' has shape {shape:?}; expected vertices × 3, 1 to \
                     {MAX_VERTICES} vertices"
                )));
            }
        };
        finite("v_template", template)?;
        let template: Vec<DVec3> = template.chunks_exact(3).map(DVec3::from_slice).collect();
        let (shape, shape_dirs) = need("shapedirs")?;
        let shape_dirs_width = match shape {
            [v, 3, s] if *v == vertices && *s > 0 => *s,
            [v, 3] if *v == vertices => 1,
            _ => {
                return Err(refuse(format!(
                    "'shapedirs' has shape {shape:?}; expected {vertices} × 3 × components"
                )));
            }
        };
        finite("shapedirs", shape_dirs)?;
        // SMPL-X's columns are shape then expression: 300 + 100, or 10 + 10 in older files.
        let (shape_count, expression_start, expression_count) = match model {
            ModelType::Smplx if shape_dirs_width >= SMPLX_SHAPE_SPACE + 100 => (
                SMPLX_SHAPE_SPACE,
                SMPLX_SHAPE_SPACE,
                shape_dirs_width - SMPLX_SHAPE_SPACE,
            ),
            ModelType::Smplx if shape_dirs_width >= 20 => (10, 10, 10),
            ModelType::Smplx => (shape_dirs_width, shape_dirs_width, 0),
            _ => (shape_dirs_width, shape_dirs_width, 0),
        };
        let features = 9 * (joints - 1);
        let (shape, pose_dirs) = need("posedirs")?;
        if shape != [vertices, 3, features] {
            return Err(refuse(format!(
                "'posedirs' has shape {shape:?}; expected {vertices} × 3 × {features} (nine a \
                 joint after the root)"
            )));
        }
        finite("posedirs", pose_dirs)?;
        let (shape, regressor) = need("J_regressor")?;
        if shape != [joints, vertices] {
            return Err(refuse(format!(
                "'J_regressor' has shape {shape:?}; expected {joints} × {vertices}"
            )));
        }
        finite("J_regressor", regressor)?;
        let regressor: Vec<Vec<(u32, f64)>> = regressor
            .chunks_exact(vertices)
            .map(|row| {
                row.iter()
                    .enumerate()
                    .filter(|(_, w)| **w != 0.0)
                    .map(|(v, &w)| (v as u32, w))
                    .collect()
            })
            .collect();
        let (shape, weights) = need("weights")?;
        if shape != [vertices, joints] {
            return Err(refuse(format!(
                "'weights' has shape {shape:?}; expected {vertices} × {joints}"
            )));
        }
        finite("weights", weights)?;
        let mut weight_start = Vec::with_capacity(vertices + 1);
        let mut sparse = Vec::new();
        for row in weights.chunks_exact(joints) {
            weight_start.push(sparse.len() as u32);
            sparse.extend(
                row.iter()
                    .enumerate()
                    .filter(|(_, w)| **w != 0.0)
                    .map(|(j, &w)| (j as u32, w)),
            );
        }
        weight_start.push(sparse.len() as u32);
        let (shape, faces) = need("f")?;
        let faces: Vec<u32> = match shape {
            [_, 3] => faces
                .iter()
                .enumerate()
                .map(|(i, &v)| {
                    (v >= 0.0 && v < vertices as f64 && v.fract() == 0.0)
                        .then_some(v as u32)
                        .ok_or_else(|| {
                            refuse(format!(
                                "'f' value {i} ({v}) is not a vertex of the {vertices}"
                            ))
                        })
                })
                .collect::<Result<_, _>>()?,
            _ => {
                return Err(refuse(format!(
                    "'f' has shape {shape:?}; expected triangles × 3"
                )));
            }
        };
        // The blend shapes, checked above, moved out rather than copied (SMPL-X's are 240 MB).
        let mut moved = |key: &str| npz.take_numbers(key).map(|(_, v)| v).unwrap_or_default();
        let (shape_dirs, pose_dirs) = (moved("shapedirs"), moved("posedirs"));
        Ok(BodyModel {
            model,
            name: shown.to_string(),
            gender: None,
            template,
            shape_dirs,
            shape_dirs_width,
            shape_count,
            expression_start,
            expression_count,
            pose_dirs,
            regressor,
            weight_start,
            weights: sparse,
            faces,
        })
    }

    /// How many vertices.
    pub fn vertex_count(&self) -> usize {
        self.template.len()
    }

    /// Vertex `v`'s skinning weights: joint (the model type's order), weight.
    pub(crate) fn weights_of(&self, v: usize) -> &[(u32, f64)] {
        &self.weights[self.weight_start[v] as usize..self.weight_start[v + 1] as usize]
    }

    /// The pose blend shapes: vertex, axis, feature (nine a joint after the root).
    pub(crate) fn pose_dirs(&self) -> &[f64] {
        &self.pose_dirs
    }

    /// How many shape components (`betas`) it has.
    pub fn shape_count(&self) -> usize {
        self.shape_count
    }

    /// How many expression components it has (SMPL-X's; none for the others).
    pub fn expression_count(&self) -> usize {
        self.expression_count
    }

    /// The body of shape `betas` (and SMPL-X's `expression`) at rest; components past the
    /// model's are not used (said by [`Shaped::betas_used`]), missing ones are zero.
    pub fn shaped(&self, betas: &[f64], expression: &[f64]) -> Result<Shaped, Error> {
        if let Some(i) = betas.iter().chain(expression).position(|v| !v.is_finite()) {
            return Err(Error::usage(format!(
                "{}: shape value {i} is not a finite number",
                self.name
            )));
        }
        let betas_used = betas.len().min(self.shape_count);
        let expression = &expression[..expression.len().min(self.expression_count)];
        let components: Vec<(usize, f64)> = (0..betas_used)
            .map(|l| (l, betas[l]))
            .chain(
                expression
                    .iter()
                    .enumerate()
                    .map(|(l, &e)| (self.expression_start + l, e)),
            )
            .collect();
        let width = self.shape_dirs_width;
        let vertices: Vec<DVec3> = self
            .template
            .iter()
            .enumerate()
            .map(|(v, t)| {
                let axis = |k: usize| {
                    let dirs = &self.shape_dirs[(3 * v + k) * width..(3 * v + k + 1) * width];
                    components.iter().map(|&(l, b)| b * dirs[l]).sum::<f64>()
                };
                *t + DVec3::new(axis(0), axis(1), axis(2))
            })
            .collect();
        let joints = self
            .regressor
            .iter()
            .map(|row| row.iter().map(|&(v, w)| vertices[v as usize] * w).sum())
            .collect();
        Ok(Shaped {
            vertices,
            joints,
            betas_used,
        })
    }

    /// Each joint's parent in the model's tree.
    pub fn parents(&self) -> Vec<Option<usize>> {
        self.model.parents()
    }

    /// The pose blend shapes' offset of every vertex for the joints' local `rotations` (the
    /// root's first, not used), added to `offsets`.
    pub fn add_pose_offsets(&self, rotations: &[DMat3], offsets: &mut [DVec3]) {
        let features = pose_features(rotations);
        let width = features.len();
        for (v, offset) in offsets.iter_mut().enumerate() {
            let axis = |k: usize| {
                let dirs = &self.pose_dirs[(3 * v + k) * width..(3 * v + k + 1) * width];
                dirs.iter().zip(&features).map(|(d, f)| d * f).sum::<f64>()
            };
            *offset += DVec3::new(axis(0), axis(1), axis(2));
        }
    }

    /// The body `shaped` posed by `pose` (an axis-angle a joint, radians, in the model type's
    /// order) and moved by `trans`: joints and vertices as `smplx` gives them.
    pub fn forward(&self, shaped: &Shaped, pose: &[f64], trans: DVec3) -> Posed {
        let rotations: Vec<DMat3> = pose
            .chunks_exact(3)
            .map(|r| rodrigues(DVec3::from_slice(r)))
            .collect();
        let parents = self.parents();
        // Each joint's frame in the world: rotation, and where its rest joint goes.
        let mut world_rotation = Vec::with_capacity(rotations.len());
        let mut world_joint: Vec<DVec3> = Vec::with_capacity(rotations.len());
        for (k, rotation) in rotations.iter().enumerate() {
            match parents[k] {
                None => {
                    world_rotation.push(*rotation);
                    world_joint.push(shaped.joints[k]);
                }
                Some(p) => {
                    let along = shaped.joints[k] - shaped.joints[p];
                    world_rotation.push(world_rotation[p] * *rotation);
                    world_joint.push(world_rotation[p] * along + world_joint[p]);
                }
            }
        }
        let mut posed_rest = shaped.vertices.clone();
        self.add_pose_offsets(&rotations, &mut posed_rest);
        let vertices = posed_rest
            .iter()
            .enumerate()
            .map(|(v, rest)| {
                let range = self.weight_start[v] as usize..self.weight_start[v + 1] as usize;
                let (mut m, mut t) = (DMat3::ZERO, DVec3::ZERO);
                for &(k, w) in &self.weights[range] {
                    let k = k as usize;
                    m += world_rotation[k] * w;
                    t += (world_joint[k] - world_rotation[k] * shaped.joints[k]) * w;
                }
                m * *rest + t + trans
            })
            .collect();
        Posed {
            joints: world_joint.iter().map(|j| *j + trans).collect(),
            vertices,
        }
    }
}

/// The pose blend shapes' features: `R − I` of every joint after the root, row by row.
pub(crate) fn pose_features(rotations: &[DMat3]) -> Vec<f64> {
    let mut features = Vec::with_capacity(9 * rotations.len().saturating_sub(1));
    for r in rotations.iter().skip(1) {
        let d = *r - DMat3::IDENTITY;
        for row in 0..3 {
            features.extend([d.col(0)[row], d.col(1)[row], d.col(2)[row]]);
        }
    }
    features
}

/// The rotation of an axis-angle (Rodrigues' formula; the zero vector is no turn).
pub(crate) fn rodrigues(axis_angle: DVec3) -> DMat3 {
    let angle = axis_angle.length();
    if angle == 0.0 {
        return DMat3::IDENTITY;
    }
    DMat3::from_axis_angle(axis_angle / angle, angle)
}

/// The gender a model file's name says (`SMPLX_FEMALE.npz`, `female/model.npz`).
fn gender_of(path: &Path) -> Option<String> {
    let said = path.to_string_lossy().to_ascii_lowercase();
    ["female", "male", "neutral"]
        .into_iter()
        .find(|g| {
            // "female" holds "male": a name says male only where "female" is not there.
            said.contains(g) && !(*g == "male" && said.contains("female"))
        })
        .map(String::from)
}

/// The model file in `folder` for `gender`: an `.npz` whose name, or whose folder's name, says
/// that gender (`SMPLH_MALE.npz`, `male/model.npz`); with no gender, the neutral one, else the
/// only one.
fn model_in_folder(
    folder: &Path,
    gender: Option<&str>,
    wanted: Option<ModelType>,
) -> Result<PathBuf, Error> {
    let mut found = Vec::new();
    let entries = |dir: &Path| -> Vec<PathBuf> {
        std::fs::read_dir(dir)
            .map(|it| it.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default()
    };
    for entry in entries(folder) {
        // A link is not followed out of the folder: only plain files and folders.
        let Ok(kind) = std::fs::symlink_metadata(&entry).map(|m| m.file_type()) else {
            continue;
        };
        if kind.is_file() && is_npz(&entry) {
            found.push(entry);
        } else if kind.is_dir() {
            for inner in entries(&entry) {
                let plain = std::fs::symlink_metadata(&inner).is_ok_and(|m| m.is_file());
                if plain && is_npz(&inner) {
                    found.push(inner);
                }
            }
        }
    }
    found.sort();
    // The type first: files whose names say another type are not candidates (a name that
    // says none, `male/model.npz`, is); then the gender among them.
    let relative = |p: &PathBuf| {
        p.strip_prefix(folder)
            .map(Path::to_path_buf)
            .unwrap_or_default()
    };
    let found: Vec<PathBuf> = found
        .into_iter()
        .filter(|p| match (wanted, type_of_name(&relative(p))) {
            (Some(wanted), Some(named)) => wanted == named,
            _ => true,
        })
        .collect();
    let wanted_gender = gender.map(|g| g.to_ascii_lowercase());
    let of_gender = |gender: &str| -> Vec<&PathBuf> {
        found
            .iter()
            .filter(|p| gender_of(&relative(p)).as_deref() == Some(gender))
            .collect()
    };
    // A gender the folder has no model of is read on its neutral one (said by the take).
    let pick: Vec<&PathBuf> = match wanted_gender.as_deref().map(of_gender) {
        Some(picked) if !picked.is_empty() => picked,
        _ => {
            let neutral = of_gender("neutral");
            if neutral.is_empty() && found.len() == 1 {
                found.iter().collect()
            } else {
                neutral
            }
        }
    };
    match pick.as_slice() {
        [one] => Ok((*one).clone()),
        [] => Err(Error::usage(format!(
            "{}: no model file for {} among its {} (a model .npz named for its gender: \
             SMPLX_NEUTRAL.npz, male/model.npz)",
            folder.display(),
            wanted_gender.as_deref().unwrap_or("a neutral body"),
            crate::io::error::counted(found.len(), ".npz file")
        ))),
        many => Err(Error::usage(format!(
            "{}: {} model files for {} ({}); give the file itself",
            folder.display(),
            many.len(),
            wanted_gender.as_deref().unwrap_or("a neutral body"),
            many.iter()
                .map(|p| p.strip_prefix(folder).unwrap_or(p).display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

/// The model type a model file's name says (`SMPLX_…`, `smplh/…`, `SMPL_…`).
fn type_of_name(path: &Path) -> Option<ModelType> {
    let said = path
        .to_string_lossy()
        .to_ascii_lowercase()
        .replace(['-', '+'], "");
    if said.contains("smplx") {
        Some(ModelType::Smplx)
    } else if said.contains("smplh") {
        Some(ModelType::Smplh)
    } else if said.contains("smpl") {
        Some(ModelType::Smpl)
    } else {
        None
    }
}

fn is_npz(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("npz"))
}
