//! The user's body model: bvhview's forward pass against the `smplx` package's, on the fake
//! models of `scripts/make_smpl_models.py` (made again by `common::smpl_models`), whose outputs
//! the script committed under `tests/data/smpl/reference/`.

use crate::common::{data, smpl_models};
use bvhview::smpl::model::BodyModel;
use bvhview::smpl::{ModelType, npz};
use glam::DVec3;

/// The committed outputs of `smplx` for `model`.
fn reference(model: ModelType) -> npz::Npz {
    let name = format!("smpl/reference/{}_smplx.npz", model.label().replace('-', "").to_lowercase());
    let bytes = std::fs::read(data(&name)).unwrap();
    npz::read(&bytes, &name).unwrap()
}

fn rows<'a>(file: &'a npz::Npz, key: &str, width: usize) -> Vec<&'a [f64]> {
    let (_, values) = file.numbers(key).unwrap_or_else(|| panic!("no {key}"));
    if width == 0 {
        return vec![&[]; 20];
    }
    values.chunks_exact(width).collect()
}

/// The fake model of `model`, built on the rest joints its reference was made on.
pub fn fake_model(model: ModelType) -> (BodyModel, npz::Npz) {
    let file = reference(model);
    let rest: Vec<[f64; 3]> = rows(&file, "rest_joints", 3)
        .iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect();
    let bytes = smpl_models::model_npz(model, &rest);
    (BodyModel::from_bytes(&bytes, "fake.npz").unwrap(), file)
}

#[test]
fn the_forward_pass_is_smplx_s_on_every_model_type() {
    for model in ModelType::ALL {
        let (body, file) = fake_model(model);
        assert_eq!(body.model, model);
        let joints = model.joint_count();
        // The same model as the script's: its template where the script sampled it.
        let index: Vec<usize> = rows(&file, "vertex_index", 1).iter().map(|r| r[0] as usize).collect();
        let rest = body.shaped(&[], &[]).unwrap();
        for (k, sample) in rows(&file, "template_sample", 3).iter().enumerate() {
            assert_eq!(rest.vertices[index[k]], DVec3::from_slice(sample), "{model:?} vertex {}", index[k]);
        }
        let expression_width = file.numbers("expression").unwrap().0[1];
        let (betas, poses, trans, expression) = (
            rows(&file, "betas", 10),
            rows(&file, "poses", 3 * joints),
            rows(&file, "trans", 3),
            rows(&file, "expression", expression_width),
        );
        let (want_joints, want_vertices) = (
            rows(&file, "joints", 3 * joints),
            rows(&file, "vertices", 3 * index.len()),
        );
        let (mut worst_joint, mut worst_vertex) = (0.0f64, 0.0f64);
        for i in 0..20 {
            let shaped = body.shaped(betas[i], expression[i]).unwrap();
            let posed = body.forward(&shaped, poses[i], DVec3::from_slice(trans[i]));
            for (j, want) in want_joints[i].chunks_exact(3).enumerate() {
                worst_joint = worst_joint.max(posed.joints[j].distance(DVec3::from_slice(want)));
            }
            for (k, want) in want_vertices[i].chunks_exact(3).enumerate() {
                worst_vertex =
                    worst_vertex.max(posed.vertices[index[k]].distance(DVec3::from_slice(want)));
            }
        }
        eprintln!("{model:?}: worst joint {worst_joint:.2e} m, worst vertex {worst_vertex:.2e} m");
        assert!(worst_joint < 1e-6, "{model:?}: a joint {worst_joint} m from smplx's");
        assert!(worst_vertex < 1e-5, "{model:?}: a vertex {worst_vertex} m from smplx's");
    }
}
