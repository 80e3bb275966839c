//! The `Character` class: a skinned mesh read from an FBX or glTF file with its skeleton
//! (`bvhview::character::Character`), takes put on it, and its skinned vertices as numpy arrays.

use crate::common::{guard, to_python};
use crate::loaded::Item;
use crate::loaded::Motion;
use crate::loading::TakeChoice;
use bvhview::character::Character as Inner;
use bvhview::model::pose::OffsetMode;
use bvhview::take::{self, Take};
use numpy::{IntoPyArray, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// A character: a skinned mesh and the skeleton it is bound to, read from an FBX or glTF file.
///
/// `motion` is the file's own take; `dress(take)` puts any take on the character (retargeted
/// onto its skeleton by role); `vertices(take, frames)` skins the mesh.
#[pyclass(frozen, module = "bvhview", name = "Character")]
pub(crate) struct Character {
    inner: Arc<Inner>,
    path: PathBuf,
}

/// Loads a character: an .fbx, .glb or .gltf file with a skinned mesh, or the user's
/// SMPL-family model file (.npz) of shape `betas` (default: the mean shape), moved by its pose
/// blend shapes and skin as `smplx` moves it. `take` picks the file's own take by name or index
/// (default: the first).
#[pyfunction]
#[pyo3(signature = (path, *, take=None, betas=None))]
pub(crate) fn load_character(
    py: Python<'_>,
    path: PathBuf,
    take: Option<TakeChoice>,
    betas: Option<Vec<f64>>,
) -> PyResult<Character> {
    guard("load_character", || {
        let inner = py
            .detach(|| {
                let mut options = take::OpenOptions::new();
                if let Some(choice) = &take {
                    options = options.take(choice.0.as_str());
                }
                if let Some(betas) = &betas {
                    options = options.betas(betas);
                }
                Inner::open_with(&path, &options)
            })
            .map_err(|e| to_python(py, e))?;
        Ok(Character {
            inner: Arc::new(inner),
            path,
        })
    })
}

impl Character {
    /// A `Motion` of a take on this character's skeleton.
    fn motion_of(&self, loaded: Take) -> Motion {
        Motion {
            loaded,
            item: Item {
                path: self.path.clone(),
                motion: None,
            },
            offset_mode: OffsetMode::Replace,
            check: None,
        }
    }
}

impl Character {
    /// `take`, or the character's own take (kept in `own`).
    fn take_or_own<'a>(&self, take: Option<&'a Motion>, own: &'a mut Option<Motion>) -> &'a Motion {
        match take {
            Some(take) => take,
            None => own.insert(self.motion()),
        }
    }
}

#[pymethods]
impl Character {
    /// The file read.
    #[getter]
    fn path(&self) -> String {
        self.path.display().to_string()
    }

    /// The file's own take on the character's skeleton (its rest pose as one frame when the
    /// file has no animation).
    #[getter]
    fn motion(&self) -> Motion {
        self.motion_of(self.inner.take.clone())
    }

    /// How many vertices the mesh has.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.inner.mesh.vertex_count()
    }

    /// The mesh's triangles, triangles × 3 vertex indices, uint32.
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        let corners = self.inner.mesh.triangles.clone();
        let count = corners.len() / 3;
        corners.into_pyarray(py).reshape([count, 3])
    }

    /// `take` put on the character: retargeted onto its skeleton by role (its rest pose
    /// aligned, its path scaled by leg length, its feet on the take's floor), a new `Motion`.
    /// A body that is not two-legged is refused unless `any_body=True`, and a result whose
    /// check against the take finds a side crossed or a width collapsed unless `force=True`;
    /// the result's `retarget_check` holds the check.
    #[pyo3(signature = (take, *, any_body=false, force=false))]
    fn dress(
        &self,
        py: Python<'_>,
        take: &Motion,
        any_body: bool,
        force: bool,
    ) -> PyResult<Motion> {
        guard("dress", || {
            let insist = bvhview::retarget::Insist { any_body, force };
            let (dressed, said) = py
                .detach(|| {
                    self.inner
                        .dress(&take.loaded, &[], insist, bvhview::plumbing::cores())
                })
                .map_err(|e| to_python(py, e))?;
            let (source_name, name) = (
                take.item.path.display().to_string(),
                self.path.display().to_string(),
            );
            crate::retarget::warn_put(py, &source_name, &name, &said.forced, &said.uncarried)?;
            let mut motion = self.motion_of(dressed);
            motion.check = said.check;
            Ok(motion)
        })
    }

    /// Writes `take` (default: the character's own take) with the character's mesh bound to
    /// it: glTF (.glb, .gltf) or FBX (.fbx), as `bvhview convert --character` does; one file an
    /// engine imports as an animated skinned character. `take` must be on the character's
    /// skeleton (its own take, or one `dress` made). The file takes its name only when
    /// complete.
    #[pyo3(signature = (path, take=None))]
    fn save(&self, py: Python<'_>, path: PathBuf, take: Option<&Motion>) -> PyResult<()> {
        guard("save", || {
            let mut own = None;
            let take = self.take_or_own(take, &mut own);
            py.detach(|| self.inner.save(&take.loaded, &path))
                .map_err(|e| to_python(py, e))
        })
    }

    /// The skinned vertices in the frames selected of `take` (default: the character's own
    /// take), frames × vertices × 3, float32, in the character's units (metres), Y up. `take`
    /// must be on the character's skeleton (its own take, or one `dress` made). `frames` as
    /// `Motion.positions` takes it; one int: no frame axis.
    #[pyo3(signature = (take=None, frames=None))]
    fn vertices<'py>(
        &self,
        py: Python<'py>,
        take: Option<&Motion>,
        frames: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        guard("vertices", || {
            let mut own = None;
            let take = self.take_or_own(take, &mut own);
            let skeleton = &take.loaded.skeleton;
            let ours = &self.inner.take.skeleton;
            let same = skeleton.joints.len() == ours.joints.len()
                && skeleton
                    .joints
                    .iter()
                    .zip(&ours.joints)
                    .all(|(a, b)| a.name == b.name);
            if !same {
                return Err(PyValueError::new_err(format!(
                    "the take is not on this character's skeleton ({} joints, {} here): put it \
                     on with character.dress(take)",
                    skeleton.joints.len(),
                    ours.joints.len()
                )));
            }
            let one = Motion::one_frame(frames);
            let chosen = take.selected_frames(frames)?;
            let count = self.inner.mesh.vertex_count();
            let values = py.detach(|| {
                let mut out = Vec::with_capacity(chosen.len() * count * 3);
                for &f in &chosen {
                    let frame = take.loaded.motion.frame(f);
                    for p in self.inner.vertices(skeleton, frame) {
                        out.extend(p.to_array());
                    }
                }
                out
            });
            let array = values.into_pyarray(py);
            Ok(if one {
                array.reshape([count, 3])?.into_any()
            } else {
                array.reshape([chosen.len(), count, 3])?.into_any()
            })
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "<bvhview.Character {}: {} vertices, {} joints, {} frames>",
            self.path.display(),
            self.inner.mesh.vertex_count(),
            self.inner.take.skeleton.joints.len(),
            self.inner.take.frame_count()
        )
    }
}
