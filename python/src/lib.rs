//! The native half of the Python package `bvhview`: a thin layer over the `bvhview` crate.
//!
//! Loading and forward kinematics are the crate's own (`take::load_checked`, `pose::FkPlan`,
//! `pose::world_matrices`, `bvh::writer::write_bvh`); this crate only moves their results into
//! numpy arrays and their errors into Python exceptions. The GIL is released for every load and
//! every computation, so Python threads run meanwhile. By concern, as `src/` is:
//! - `loaded`: what the `Motion` class holds (a loaded take, and the `Item` it came from);
//! - `motion`: the `Motion` class's properties and methods (thin);
//! - `loading`: `load`, `load_many`, and which take of a file;
//! - `character`: the `Character` class (a skinned mesh), `load_character`;
//! - `arrays`: frames chosen, positions, matrices and rotations as numpy arrays;
//! - `edits`: edits that make a new take, and `Motion.from_arrays`;
//! - `pickle`: a take pickled whole and rebuilt, checked;
//! - `datasets`: `list_takes`, the dataset compile and merge, the checked reader, the way back;
//! - `retarget`: retargeting, positions and HumanML3D's vectors to a take;
//! - `common`: errors as Python exceptions, and the guard every entry point runs in so that no
//!   panic reaches Python;
//! - here: the module, which names each module's entry points. The modules import from one
//!   another by name, never from here.

mod arrays;
mod character;
mod common;
mod datasets;
mod edits;
mod loaded;
mod loading;
mod motion;
mod pickle;
mod retarget;

use character::{Character, load_character};
use common::ParseError;
use datasets::{
    _compile_dataset, _dataset_manifest, _dataset_motion, _merge_datasets, _open_dataset,
    list_takes,
};
use loaded::Motion;
use loading::{load, load_many};
use numpy::{IntoPyArray, PyArrayMethods};
use pickle::_from_state;
use pyo3::prelude::*;

/// Load BVH and ASF/AMC motion capture into numpy arrays (bvhview's Rust loader and FK).
#[pymodule]
fn _bvhview(module: &Bound<'_, PyModule>) -> PyResult<()> {
    // One-time setup done at import, as a C extension's `import_array()` in its module init:
    // numpy's C API, the numpy crate's shared borrow flags and the owner type of arrays made
    // from Rust vectors (each fetched on first use otherwise), and the core count (which reads
    // the cgroup's CPU limits): some 0.6 ms the first load and arrays would pay otherwise.
    let empty = numpy::PyArray1::<f32>::zeros(module.py(), 0, false);
    drop(empty.try_readwrite());
    Vec::<f32>::new().into_pyarray(module.py());
    bvhview::plumbing::cores();
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    module.add_function(wrap_pyfunction!(load, module)?)?;
    module.add_function(wrap_pyfunction!(load_many, module)?)?;
    module.add_function(wrap_pyfunction!(loading::metrics, module)?)?;
    module.add_function(wrap_pyfunction!(_from_state, module)?)?;
    module.add_function(wrap_pyfunction!(list_takes, module)?)?;
    module.add_function(wrap_pyfunction!(_compile_dataset, module)?)?;
    module.add_function(wrap_pyfunction!(_merge_datasets, module)?)?;
    module.add_function(wrap_pyfunction!(_open_dataset, module)?)?;
    module.add_function(wrap_pyfunction!(_dataset_manifest, module)?)?;
    module.add_function(wrap_pyfunction!(retarget::humanml3d_features, module)?)?;
    module.add_function(wrap_pyfunction!(_dataset_motion, module)?)?;
    module.add_class::<Motion>()?;
    module.add_class::<Character>()?;
    module.add_function(wrap_pyfunction!(load_character, module)?)?;
    module.add("ParseError", module.py().get_type::<ParseError>())?;
    Ok(())
}
