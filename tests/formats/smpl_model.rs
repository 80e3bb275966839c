//! The user's body model: bvhview's forward pass against the `smplx` package's, on the fake
//! models of `scripts/make_smpl_models.py` (made again by `common::smpl_models`), whose outputs
//! the script committed under `tests/smpl/`.

use crate::common::{data, smpl_models};
use bvhview::smpl::model::BodyModel;
use bvhview::smpl::{ModelType, amass, npz};
use glam::DVec3;

/// A folder of its own for a test's files, removed when the test ends: model files are hundreds
/// of megabytes, and a kept folder a run would fill a disk.
fn scratch(label: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("bvhview-{label}-"))
        .tempdir()
        .unwrap()
}

/// The committed outputs of `smplx` for `model`.
fn reference(model: ModelType) -> npz::Npz {
    let name = format!(
        "tests/smpl/{}_smplx.npz",
        model.label().replace('-', "").to_lowercase()
    );
    let bytes =
        std::fs::read(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(&name)).unwrap();
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
        let index: Vec<usize> = rows(&file, "vertex_index", 1)
            .iter()
            .map(|r| r[0] as usize)
            .collect();
        let rest = body.shaped(&[], &[]).unwrap();
        for (k, sample) in rows(&file, "template_sample", 3).iter().enumerate() {
            assert_eq!(
                rest.vertices[index[k]],
                DVec3::from_slice(sample),
                "{model:?} vertex {}",
                index[k]
            );
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
        assert!(
            worst_joint < 1e-6,
            "{model:?}: a joint {worst_joint} m from smplx's"
        );
        assert!(
            worst_vertex < 1e-5,
            "{model:?}: a vertex {worst_vertex} m from smplx's"
        );
    }
}

/// The fake model of `model` written as a model file in `folder`, named as the real ones are.
fn model_file(model: ModelType, folder: &std::path::Path) -> std::path::PathBuf {
    let file = reference(model);
    let rest: Vec<[f64; 3]> = rows(&file, "rest_joints", 3)
        .iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect();
    let name = format!("{}_NEUTRAL.npz", model.label().replace('-', ""));
    let path = folder.join(name);
    std::fs::write(&path, smpl_models::model_npz(model, &rest)).unwrap();
    path
}

/// An AMASS file read with the user's model: every joint of every frame where the model's
/// forward pass puts it (the file's betas, `trans`, Z up turned to Y up), and written again
/// the same arrays, betas and gender kept.
#[test]
fn an_amass_file_read_on_a_model_stands_where_the_model_puts_it() {
    let folder_scratch = scratch("body-model");
    let folder = folder_scratch.path().to_path_buf();
    for (file, model) in [
        ("smpl/amass_smplh_walk.npz", ModelType::Smplh),
        ("smpl/amass_smplx_walk.npz", ModelType::Smplx),
        ("smpl/smpl_walk_compressed.npz", ModelType::Smpl),
    ] {
        model_file(model, &folder);
        let take = bvhview::OpenOptions::new()
            .body_model(&folder)
            .open(data(file))
            .unwrap();
        let said: Vec<String> = take.warnings.iter().map(|w| w.to_string()).collect();
        assert!(
            said.iter()
                .any(|w| w.contains("read on the body of") && w.contains("NEUTRAL.npz")),
            "{file}: {said:?}"
        );
        let bytes = std::fs::read(data(file)).unwrap();
        let params = amass::read(&npz::read(&bytes, file).unwrap(), file, None).unwrap();
        let body = BodyModel::open(&folder, None, Some(model), u64::MAX).unwrap();
        let shaped = body.shaped(&params.betas, &[]).unwrap();
        let names = model.joint_names();
        let width = model.pose_width();
        let mut worst = 0.0f64;
        // Every seventh frame: the forward pass of a debug build is slow.
        for f in (0..take.frame_count()).step_by(7) {
            let trans = DVec3::from_slice(&params.trans[3 * f..3 * f + 3]);
            let posed = body.forward(&shaped, &params.poses[f * width..(f + 1) * width], trans);
            let got = take.positions(f).unwrap();
            for (j, joint) in take.skeleton.joints.iter().enumerate() {
                let Some(k) = names.iter().position(|n| *n == joint.name) else {
                    continue;
                };
                let p = posed.joints[k];
                // AMASS's Z up in bvhview's Y up: (x, y, z) → (x, z, −y).
                let want = DVec3::new(p.x, p.z, -p.y);
                worst = worst.max(got[j].as_dvec3().distance(want));
            }
        }
        assert!(worst < 1e-5, "{file}: a joint {worst} m from the model's");
        let (written, _) = take.amass().unwrap();
        let back = amass::read(&npz::read(&written, "back.npz").unwrap(), "back", None).unwrap();
        // A file that says no gender is written neutral.
        let gender = params.gender.clone().or(Some("neutral".into()));
        assert_eq!(
            (&back.betas, &back.gender),
            (&params.betas, &gender),
            "{file}"
        );
        let far = |a: &[f64], b: &[f64]| {
            a.iter()
                .zip(b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max)
        };
        assert!(
            far(&back.trans, &params.trans) < 1e-6,
            "{file}: trans {}",
            far(&back.trans, &params.trans)
        );
        assert!(far(&back.poses, &params.poses) < 1e-6, "{file}: poses");
    }
}

/// The body model as a character: its mesh skinned by bvhview's drawing path (32-bit floats,
/// pose blend shapes, linear blend skinning) where `smplx` puts every vertex, for an AMASS
/// take of each reference body (its pose, betas and trans) put on it.
#[test]
fn a_body_model_character_is_skinned_as_smplx_skins_it() {
    use crate::common::npz::{f64s, npy, npz as archive};
    for model in ModelType::ALL {
        let (body, file) = fake_model(model);
        let body = std::sync::Arc::new(body);
        let joints = model.joint_count();
        let index: Vec<usize> = rows(&file, "vertex_index", 1)
            .iter()
            .map(|r| r[0] as usize)
            .collect();
        let expression_width = file.numbers("expression").unwrap().0[1];
        let (betas, poses, trans, expression) = (
            rows(&file, "betas", 10),
            rows(&file, "poses", 3 * joints),
            rows(&file, "trans", 3),
            rows(&file, "expression", expression_width),
        );
        let want = rows(&file, "vertices", 3 * index.len());
        let mut worst = 0.0f64;
        // Four bodies of the twenty: each is a character of its own shape.
        for i in [0, 5, 11, 19] {
            let character = bvhview::character::Character::from_body_model(
                body.clone(),
                Some(betas[i]),
                expression[i],
            )
            .unwrap();
            let take = bvhview::OpenOptions::new()
                .format(bvhview::take::Format::Amass)
                .open_bytes(
                    &archive(
                        &[
                            ("poses.npy", npy("<f8", &[1, 3 * joints], &f64s(poses[i]))),
                            ("trans.npy", npy("<f8", &[1, 3], &f64s(trans[i]))),
                            ("betas.npy", npy("<f8", &[10], &f64s(betas[i]))),
                            ("mocap_framerate.npy", npy("<f8", &[], &f64s(&[30.0]))),
                        ],
                        false,
                    ),
                    "body.npz",
                )
                .unwrap();
            let (dressed, said) = character
                .dress_file(
                    &take,
                    std::path::Path::new("body.npz"),
                    Default::default(),
                    1,
                )
                .unwrap();
            assert!(
                said.check.is_none(),
                "{model:?}: retargeted, not put on as it is"
            );
            let vertices = character.vertices(&dressed.skeleton, dressed.frame(0).unwrap());
            for (k, w) in want[i].chunks_exact(3).enumerate() {
                // smplx's Z up in the take's Y up.
                let w = DVec3::new(w[0], w[2], -w[1]);
                worst = worst.max(vertices[index[k]].as_dvec3().distance(w));
            }
        }
        eprintln!("{model:?}: worst skinned vertex {worst:.2e} m");
        assert!(worst < 1e-5, "{model:?}: a vertex {worst} m from smplx's");
    }
}

/// Betas fitted to a figure of the model's own shape give that figure's bones back: the
/// model shaped by known betas, then fitted from its skeleton alone.
#[test]
fn betas_fitted_to_a_body_of_the_model_give_its_bones_back() {
    for model in ModelType::ALL {
        let (body, _) = fake_model(model);
        let body = std::sync::Arc::new(body);
        let truth = [1.5, -0.8, 0.6, 2.0, -1.2, 0.3, -0.4, 1.1, -2.0, 0.9];
        let shaped =
            bvhview::character::Character::from_body_model(body.clone(), Some(&truth), &[])
                .unwrap();
        let fitted = bvhview::smpl::fit::shaped_to(&body, &shaped.take.skeleton, 1.0).unwrap();
        let (want, got) = (&shaped.take.skeleton, &fitted.skeleton);
        let mut worst = 0.0f32;
        for (a, b) in want.joints.iter().zip(&got.joints) {
            assert_eq!(a.name, b.name);
            if !a.end_site && a.parent.is_some() {
                worst = worst.max((a.offset.length() - b.offset.length()).abs());
            }
        }
        assert!(
            fitted.said.contains("→ 0.0% median"),
            "{model:?}: {}",
            fitted.said
        );
        assert!(
            worst < 1e-4,
            "{model:?}: a bone {worst} m from the shaped body's"
        );
    }
}

/// Any take put on the user's model (betas fitted to its bones), written as AMASS's `.npz`
/// and read back with the model: every joint where the take on the model had it, within 1e-4
/// of its height; the betas and gender written are the fitted body's.
#[test]
fn a_take_put_on_a_model_and_written_reads_back_where_it_was() {
    let folder_scratch = scratch("fitted");
    let folder = folder_scratch.path().to_path_buf();
    let walk = bvhview::Take::open(data("bvh/bvh11_131_01.bvh"))
        .unwrap()
        .trim(0..120);
    let metres = f64::from(walk.stance(walk.offset_mode).units.metres);
    for model in ModelType::ALL {
        model_file(model, &folder);
        let body = bvhview::smpl::open_model(&folder, None, Some(model), u64::MAX).unwrap();
        let fitted = bvhview::smpl::fit::shaped_to(&body, &walk.skeleton, metres).unwrap();
        let target = bvhview::retarget::Target::new("model".into(), fitted.skeleton, &fitted.rest);
        let put = target
            .apply_up(
                "walk",
                &walk.skeleton,
                &walk.motion,
                None,
                &[],
                Default::default(),
                1,
            )
            .unwrap();
        let mut take = bvhview::Take::new(put.skeleton, put.motion, "walk on the model");
        take.body = Some(fitted.body.clone());
        let (bytes, _) = take.amass().unwrap();
        let written = amass::read(&npz::read(&bytes, "w.npz").unwrap(), "w", None).unwrap();
        assert_eq!(written.betas, fitted.body.betas, "{model:?}");
        assert!(
            written.betas.iter().any(|b| *b != 0.0),
            "{model:?}: no betas fitted"
        );
        let back = bvhview::OpenOptions::new()
            .body_model(&folder)
            .format(bvhview::take::Format::Amass)
            .open_bytes(&bytes, "w.npz")
            .unwrap();
        let height = f64::from(take.stance(take.offset_mode).height);
        let mut worst = 0.0f64;
        for f in (0..take.frame_count()).step_by(10) {
            let (a, b) = (take.positions(f).unwrap(), back.positions(f).unwrap());
            for (j, joint) in take.skeleton.joints.iter().enumerate() {
                if joint.end_site {
                    continue;
                }
                let k = back
                    .skeleton
                    .joints
                    .iter()
                    .position(|b| b.name == joint.name)
                    .unwrap();
                worst = worst.max(f64::from(a[j].distance(b[k])));
            }
        }
        assert!(
            worst < 1e-4 * height,
            "{model:?}: a joint {worst} m away (height {height})"
        );
    }
}

/// Model files that are not what they say: each refused by name, nothing used before it holds.
#[test]
fn hostile_model_files_are_refused_by_name() {
    use crate::common::npz::{f64s, npy, npz as archive};
    let (body, file) = fake_model(ModelType::Smpl);
    drop(body);
    let rest: Vec<[f64; 3]> = rows(&file, "rest_joints", 3)
        .iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect();
    let good = smpl_models::model_npz(ModelType::Smpl, &rest);
    let members = npz::read(&good, "good.npz").unwrap();
    // The good model's members, as bytes, with one replaced or left out.
    let rebuilt = |replace: &str, with: Option<Vec<u8>>| -> Vec<u8> {
        let mut out: Vec<(String, Vec<u8>)> = Vec::new();
        for name in members.names() {
            let bytes = if name == replace {
                match &with {
                    Some(bytes) => bytes.clone(),
                    None => continue,
                }
            } else {
                let (shape, values) = members.numbers(name).unwrap();
                npy("<f8", shape, &f64s(values))
            };
            out.push((format!("{name}.npy"), bytes));
        }
        archive(&out, false)
    };
    let refused = |bytes: Vec<u8>| {
        BodyModel::from_bytes(&bytes, "hostile.npz")
            .unwrap_err()
            .to_string()
    };
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "no posedirs",
            rebuilt("posedirs", None),
            "no 'posedirs' array",
        ),
        (
            "a pickled J_regressor",
            rebuilt("J_regressor", Some(npy("|O", &[], b"\x80\x02N."))),
            "'J_regressor' is an array of dtype",
        ),
        (
            "posedirs of another type's width",
            rebuilt(
                "posedirs",
                Some(npy("<f8", &[6890, 3, 9], &f64s(&vec![0.0; 6890 * 27]))),
            ),
            "'posedirs' has shape [6890, 3, 9]; expected 6890 × 3 × 207",
        ),
        (
            "a weight that is not a number",
            rebuilt(
                "weights",
                Some(npy(
                    "<f8",
                    &[6890, 24],
                    &f64s(&[&[f64::NAN][..], &vec![0.0; 6890 * 24 - 1]].concat()),
                )),
            ),
            "'weights' value 0 is not a finite number",
        ),
        (
            "a triangle past the vertices",
            rebuilt("f", Some(npy("<f8", &[1, 3], &f64s(&[0.0, 1.0, 6890.0])))),
            "'f' value 2 (6890) is not a vertex of the 6890",
        ),
        (
            "a tree of 23 joints",
            rebuilt(
                "kintree_table",
                Some(npy("<f8", &[2, 23], &f64s(&vec![0.0; 46]))),
            ),
            "its tree has 23 joints; SMPL has 24, SMPL-H 52, SMPL-X 55",
        ),
        (
            "a tree whose knee hangs from the wrong hip",
            rebuilt(
                "kintree_table",
                Some({
                    let mut tree: Vec<f64> = ModelType::Smpl
                        .parents()
                        .iter()
                        .map(|p| p.map_or(-1.0, |p| p as f64))
                        .collect();
                    tree[4] = 2.0;
                    tree.extend((0..24).map(|k| k as f64));
                    npy("<f8", &[2, 24], &f64s(&tree))
                }),
            ),
            "'kintree_table' column 4 says joint 4 under 2; SMPL's joint 4 (left_knee) is under 1",
        ),
    ];
    for (what, bytes, said) in cases {
        let message = refused(bytes);
        assert!(message.contains(said), "{what}: {message}");
    }
    // An AMASS motion file given as a model says what it is.
    let motion = std::fs::read(data("smpl/amass_smplh_walk.npz")).unwrap();
    assert!(refused(motion).contains("this is a motion file, AMASS's"));
    // A pickled model file is never opened.
    let folder_scratch = scratch("pickle");
    let folder = folder_scratch.path().to_path_buf();
    std::fs::write(folder.join("SMPL_NEUTRAL.pkl"), b"\x80\x02N.").unwrap();
    let message = BodyModel::open(&folder.join("SMPL_NEUTRAL.pkl"), None, None, u64::MAX)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("a pickled model file (.pkl) is not read"),
        "{message}"
    );
}

/// A folder of model files: the one of the motion's gender, else the neutral one; a link in
/// it is not followed out of it; several of one gender and type, named.
#[test]
fn a_model_is_found_in_a_folder_by_gender_and_type() {
    let folder_scratch = scratch("models");
    let folder = folder_scratch.path().to_path_buf();
    let neutral = model_file(ModelType::Smplh, &folder);
    // The male one, in a folder of its own as AMASS's downloads have it.
    std::fs::create_dir(folder.join("male")).unwrap();
    std::fs::copy(&neutral, folder.join("male/model.npz")).unwrap();
    let open =
        |gender| BodyModel::open(&folder, gender, Some(ModelType::Smplh), u64::MAX).map(|m| m.name);
    assert!(open(Some("male")).unwrap().ends_with("male/model.npz"));
    assert!(
        open(Some("female")).unwrap().ends_with("SMPLH_NEUTRAL.npz"),
        "no female: the neutral one"
    );
    assert!(open(None).unwrap().ends_with("SMPLH_NEUTRAL.npz"));
    // A link named as a female model, pointing out of the folder: not followed.
    let outside_scratch = scratch("outside");
    let outside = outside_scratch.path().to_path_buf();
    std::fs::copy(&neutral, outside.join("elsewhere.npz")).unwrap();
    std::os::unix::fs::symlink(
        outside.join("elsewhere.npz"),
        folder.join("SMPLH_FEMALE.npz"),
    )
    .unwrap();
    assert!(open(Some("female")).unwrap().ends_with("SMPLH_NEUTRAL.npz"));
    // The type before the gender: a male SMPL-X take in a folder of a male SMPL-H model and a
    // neutral SMPL-X one is read on the SMPL-X one.
    let mixed_scratch = scratch("mixed");
    let mixed = mixed_scratch.path().to_path_buf();
    std::fs::copy(&neutral, mixed.join("SMPLH_MALE.npz")).unwrap();
    model_file(ModelType::Smplx, &mixed);
    let picked = BodyModel::open(&mixed, Some("male"), Some(ModelType::Smplx), u64::MAX).unwrap();
    assert!(
        picked.name.ends_with("SMPLX_NEUTRAL.npz"),
        "{}",
        picked.name
    );
    // The gender is the file's name's, or its folder's, never a folder's further up.
    let study_scratch = scratch("female_study");
    let study = study_scratch.path().to_path_buf();
    let file = model_file(ModelType::Smpl, &study);
    let model = BodyModel::open(&file, None, None, u64::MAX).unwrap();
    assert_eq!(
        model.gender.as_deref(),
        Some("neutral"),
        "{}",
        file.display()
    );
    // Two neutral SMPL-H files: named, none picked.
    std::fs::copy(&neutral, folder.join("smplh_neutral_copy.npz")).unwrap();
    let message = open(None).unwrap_err().to_string();
    assert!(
        message.contains("2 model files for a neutral body"),
        "{message}"
    );
}

/// A body model character written as glTF: its pose blend shapes are morph targets whose
/// weights move every vertex, before the skin, as bvhview's own drawing moves it on every frame
/// (the glTF specification's sum, done here from the file; Blender 5.2's importer agreed within
/// 1e-6 m when this was written, see tests/smpl/README.md).
#[cfg(feature = "gltf")]
#[test]
fn a_body_model_written_as_gltf_carries_its_pose_blend_shapes() {
    let (body, _) = fake_model(ModelType::Smpl);
    let character =
        bvhview::character::Character::from_body_model(std::sync::Arc::new(body), None, &[])
            .unwrap();
    let walk = bvhview::Take::open(data("smpl/smpl_walk_compressed.npz"))
        .unwrap()
        .trim(0..12);
    let (take, _) = character.dress(&walk, &[], Default::default(), 1).unwrap();
    let folder_scratch = scratch("body-gltf");
    let folder = folder_scratch.path().to_path_buf();
    let path = folder.join("body.glb");
    character.save(&take, &path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let file = gltf::Gltf::from_slice(&bytes).unwrap();
    let blob = file.blob.as_deref();
    let primitive = file.meshes().next().unwrap().primitives().next().unwrap();
    let reader = primitive.reader(|_| blob);
    let rest: Vec<glam::Vec3> = reader
        .read_positions()
        .unwrap()
        .map(glam::Vec3::from)
        .collect();
    let targets: Vec<Vec<glam::Vec3>> = reader
        .read_morph_targets()
        .map(|(positions, _, _)| positions.unwrap().map(glam::Vec3::from).collect())
        .collect();
    assert!(targets.len() > 100, "{} targets", targets.len());
    let animation = file.animations().next().unwrap();
    let weights: Vec<f32> = animation
        .channels()
        .find_map(|channel| match channel.reader(|_| blob).read_outputs()? {
            gltf::animation::util::ReadOutputs::MorphTargetWeights(w) => {
                Some(w.into_f32().collect())
            }
            _ => None,
        })
        .unwrap();
    assert_eq!(weights.len(), take.frame_count() * targets.len());
    assert!(
        weights.iter().all(|w| *w >= 0.0),
        "a negative weight (Blender reads it as 0)"
    );
    let blend = character.mesh.pose_blend.as_deref().unwrap();
    let mut world = Vec::new();
    let mut worst = 0.0f32;
    for f in 0..take.frame_count() {
        let row = &weights[f * targets.len()..(f + 1) * targets.len()];
        bvhview::model::pose::world_matrices(
            &take.skeleton,
            take.frame(f).unwrap(),
            take.offset_mode,
            &mut world,
        );
        let want = blend.apply(&rest, &world);
        for (v, want) in want.iter().enumerate() {
            let got = rest[v]
                + targets
                    .iter()
                    .zip(row)
                    .map(|(t, w)| t[v] * *w)
                    .sum::<glam::Vec3>();
            worst = worst.max(got.distance(*want));
        }
    }
    assert!(
        worst < 1e-6,
        "a vertex {worst} m from bvhview's pose blend shapes"
    );
}

/// A model of another type than an AMASS file's (given for a target) does not read it: said,
/// and the take is read on the built-in figure.
#[test]
fn a_model_of_another_type_does_not_read_a_take() {
    let folder_scratch = scratch("other-type");
    let folder = folder_scratch.path().to_path_buf();
    let smplx = model_file(ModelType::Smplx, &folder);
    let take = bvhview::OpenOptions::new()
        .body_model(&smplx)
        .open(data("smpl/amass_smplh_walk.npz"))
        .unwrap();
    let said: Vec<String> = take.warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        said.iter()
            .any(|w| w.contains("the body model does not read this take")
                && w.contains("a SMPL-X model, and the motion is SMPL-H parameters")),
        "{said:?}"
    );
    assert!(take.body.unwrap().rest_pelvis.is_none());
}

/// Betas fitted to positions are the same whatever units the positions are in (a CMU take's
/// `positions` are centimetres, a model's output metres): the units are read from their size.
#[test]
fn betas_fitted_to_positions_do_not_depend_on_their_units() {
    let (body, _) = fake_model(ModelType::Smpl);
    let walk = bvhview::Take::open(data("bvh/bvh11_131_01.bvh"))
        .unwrap()
        .trim(0..30);
    let metres = f64::from(walk.stance(walk.offset_mode).units.metres);
    let keypoints =
        bvhview::solve::layouts::of_take(&walk, bvhview::solve::layouts::Layout::Smpl24, metres)
            .unwrap();
    let placed = bvhview::solve::layouts::to_smpl(&keypoints, 0.3, None, "k").unwrap();
    let in_metres = bvhview::smpl::fit::shaped_to_positions(&body, &placed.positions).unwrap();
    let mut in_cm = placed.positions.clone();
    for p in &mut in_cm.points {
        *p *= 100.0;
    }
    let from_cm = bvhview::smpl::fit::shaped_to_positions(&body, &in_cm).unwrap();
    assert!(
        from_cm.said.contains("read as centimetres"),
        "{}",
        from_cm.said
    );
    for (a, b) in in_metres.body.betas.iter().zip(&from_cm.body.betas) {
        assert!(
            (a - b).abs() < 1e-5,
            "{:?} {:?}",
            in_metres.body.betas,
            from_cm.body.betas
        );
    }
}

/// The fit lowers the median relative length difference it prints, on every take of the
/// repository that maps onto the model (the relative misses through a robust loss: a collar or
/// hip joint defined otherwise does not pull the other bones off), or keeps the mean shape and
/// says so: never a fit that leaves the bones further off than the mean shape.
#[test]
fn a_fit_lowers_the_median_difference_or_keeps_the_mean_shape() {
    let folder_scratch = scratch("robust_fit");
    let folder = folder_scratch.path().to_path_buf();
    model_file(ModelType::Smplh, &folder);
    let body = bvhview::smpl::open_model(&folder, None, Some(ModelType::Smplh), u64::MAX).unwrap();
    let percent = |said: &str| -> Vec<f64> {
        said.split('%')
            .filter_map(|part| part.rsplit([' ', ',']).next()?.parse().ok())
            .collect()
    };
    let (mut fitted_count, mut kept) = (0, Vec::new());
    for entry in std::fs::read_dir(data("bvh")).unwrap() {
        let path = entry.unwrap().path();
        let Ok(take) = bvhview::Take::open(&path) else {
            continue;
        };
        let metres = f64::from(take.stance(take.offset_mode).units.metres);
        let Ok(fitted) = bvhview::smpl::fit::shaped_to(&body, &take.skeleton, metres) else {
            continue;
        };
        let figures = percent(&fitted.said);
        if fitted.body.betas.iter().all(|b| *b == 0.0) {
            assert!(fitted.said.contains("mean shape"), "{}", fitted.said);
            kept.push(path.file_name().unwrap().to_string_lossy().into_owned());
        } else {
            assert_eq!(figures.len(), 2, "{}", fitted.said);
            assert!(
                figures[1] <= figures[0],
                "{}: {}",
                path.display(),
                fitted.said
            );
            fitted_count += 1;
        }
    }
    // The CMU walk's median falls from 23.3% to 7.6% on the fake SMPL-H model.
    assert!(fitted_count >= 12, "{fitted_count} fitted, kept: {kept:?}");
    assert_eq!(kept, ["bvhparser_simple.bvh"]);
}
