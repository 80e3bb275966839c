//! The ids of a written file's objects and the names of the properties it animates, which the
//! scene and its bones both write.

/// Object ids: the scene's root is 0; everything else counts up from here (any positive
/// 64-bit id is an id; fixed ones make the same take the same bytes).
const FIRST_ID: i64 = 1_000_000;

/// The ids of one bone's objects.
pub(super) fn model_id(bone: usize) -> i64 {
    FIRST_ID + 16 * bone as i64
}

/// The id of one bone's `NodeAttribute`.
pub(super) fn attribute_id(bone: usize) -> i64 {
    model_id(bone) + 1
}

/// Property `p` (0 translation, 1 rotation): its curve node, then its three curves.
pub(super) fn curve_node_id(bone: usize, p: usize) -> i64 {
    model_id(bone) + 2 + 4 * p as i64
}

/// The id of the curve of one axis (0 X, 1 Y, 2 Z) of property `p` of one bone.
pub(super) fn curve_id(bone: usize, p: usize, axis: usize) -> i64 {
    curve_node_id(bone, p) + 1 + axis as i64
}

/// A character's meshes: part `k`'s `Model`, `Geometry` and skin `Deformer` (past every
/// bone's ids: a bone's run up from [`FIRST_ID`] in steps of 16).
const FIRST_MESH_ID: i64 = 1 << 40;

pub(super) fn mesh_model_id(part: usize) -> i64 {
    FIRST_MESH_ID + 4 * part as i64
}

pub(super) fn geometry_id(part: usize) -> i64 {
    mesh_model_id(part) + 1
}

pub(super) fn skin_id(part: usize) -> i64 {
    mesh_model_id(part) + 2
}

/// The cluster of mesh bone `bone` (an index into the mesh's bones, unique across its parts).
pub(super) fn cluster_id(bone: usize) -> i64 {
    (1 << 41) + bone as i64
}

/// The one animation stack, its one layer, the bind pose and the document.
pub(super) const STACK_ID: i64 = 10;
pub(super) const LAYER_ID: i64 = 11;
pub(super) const POSE_ID: i64 = 12;
pub(super) const DOCUMENT_ID: i64 = 13;

/// The animated properties, by index.
pub(super) const PROPERTIES: [(&str, &str); 2] = [("Lcl Translation", "T"), ("Lcl Rotation", "R")];
/// A curve node's three curves, by axis.
pub(super) const AXES: [&str; 3] = ["d|X", "d|Y", "d|Z"];
