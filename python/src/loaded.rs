//! Python's `Motion` as it is held: a loaded take, what it was loaded from (`Item`), its offset
//! mode and what measured it. The class's methods live by concern in `motion`, `arrays`,
//! `edits`, `pickle` and `retarget`, each a `#[pymethods]` block of its own.

use bvhview::model::pose::OffsetMode;
use bvhview::take::Take;
use pyo3::prelude::*;
use std::path::PathBuf;

/// One thing to load: a BVH file, or an ASF skeleton with an optional AMC motion.
#[derive(Clone, Debug)]
pub(crate) struct Item {
    pub(crate) path: PathBuf,
    pub(crate) motion: Option<PathBuf>,
}

/// A loaded take: the skeleton, the MOTION values, and forward kinematics on them.
///
/// Frozen: nothing changes after loading, so `values` can be a view of the loaded data (no
/// copy) and computations can read it without the GIL.
#[pyclass(frozen, module = "bvhview", name = "Motion")]
pub(crate) struct Motion {
    pub(crate) loaded: Take,
    pub(crate) item: Item,
    pub(crate) offset_mode: OffsetMode,
    /// What the retarget that made this take measured it against its source; edits and
    /// pickling drop it (what was measured is then not this take).
    pub(crate) check: Option<bvhview::retarget::Check>,
}
