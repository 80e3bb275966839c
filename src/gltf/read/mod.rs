//! glTF 2.0 (`.gltf` with its buffers, or `.glb`) → the same `Skeleton` + `Motion` a BVH loads
//! into. The writer is [`crate::gltf`]; this is the reader beside it.
//!
//! The skeleton is the joints of the file's skins (with the nodes between them), or, in a file
//! without a skin, every animated node (with the nodes between them). Each animation is a take;
//! its frames are sampled at the rate of its keys (the key step that puts the most keys on a
//! frame, see `timing`; a warning when some keys fall between frames), every frame interpolated
//! as the file says (`STEP`, `LINEAR` with slerp for rotations, `CUBICSPLINE`), and the world
//! matrices go through `model::baked`. glTF is Y up and in metres, bvhview's own convention:
//! nothing is converted.
//!
//! A file is hostile until read: buffers are taken only from the GLB's own chunk, from `data:`
//! URIs, or from files inside the `.gltf`'s own folder (no absolute path, no `..`, no scheme, no
//! symbolic link out), each a regular file (a FIFO, device or socket is refused before a read),
//! at least as long as its `byteLength` and read only that far, no longer than `--max-size` and
//! [`crate::limits::MAX_WHOLE_FILE_BYTES`]; every accessor's bytes are checked to lie inside its
//! buffer before they are read, and each is decoded once however many channels share it; an
//! animation's channels may ask for [`KEY_VALUES_PER_BYTE`] key values per byte of input, and
//! its frames × (joints + tracks) at most `baked::FRAME_WORK_PER_BYTE` per byte (each above
//! a floor), refused past them before the work; a key that is not a finite number is refused
//! by node, key and time; the node tree is checked for cycles and shared children.

use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::baked::{self, Node, Pose};
use crate::model::reading::{Read, TakeInfo, choose_take, pick_take};
use crate::take::options::OpenOptions;
use glam::{DMat4, DQuat, DVec3};
use gltf::animation::Property;
use std::path::Path;

mod file;
mod mesh;
mod tracks;

use file::{File, bad, parse, read};
pub use tracks::{KEY_VALUES_FLOOR, KEY_VALUES_PER_BYTE};
use tracks::{Timing, Track, frames_within, timing, tracks};

fn animation_name(animation: &gltf::Animation) -> String {
    animation
        .name()
        .map(str::to_string)
        .unwrap_or_else(|| format!("animation{}", animation.index()))
}

/// The takes of a glTF file (its animations), in file order.
pub fn takes(path: &Path, max_size: u64) -> Result<Vec<TakeInfo>, Error> {
    let file = read(path, max_size)?;
    let path = &path.display().to_string();
    file.gltf
        .document
        .animations()
        .map(|animation| {
            let tracks = tracks(&file, &animation).map_err(|why| bad(path, why))?;
            let timing = timing(&tracks);
            let joints = tracks
                .iter()
                .map(|t| t.node)
                .collect::<std::collections::HashSet<_>>()
                .len();
            let frames = frames_within(&timing, joints, joints, tracks.len(), file.bytes)
                .map_err(|why| bad(path, why))?;
            Ok(TakeInfo {
                name: animation_name(&animation),
                frames,
                frame_time: 1.0 / timing.fps,
            })
        })
        .collect()
}

/// `q` normalized; the identity when it has no length (or is not finite).
fn unit(q: DQuat) -> DQuat {
    let length = q.length();
    if length.is_finite() && length > 1e-12 {
        q / length
    } else {
        DQuat::IDENTITY
    }
}

/// Local translation, rotation, scale of every node (its static transform).
type Trs = (DVec3, DQuat, DVec3);

fn trs_matrix(trs: &Trs) -> DMat4 {
    DMat4::from_scale_rotation_translation(trs.2, trs.1, trs.0)
}

/// Reads the glTF at `path` with `options` (its take, by an animation's name or index, the
/// first unless [`OpenOptions::take`] names another; its size limit).
pub fn load(path: &Path, options: &OpenOptions) -> Result<Read, Error> {
    let file = read(path, options.max_size_or_default())?;
    let take = options.take.as_deref();
    load_file(&file, &path.display().to_string(), take, false).map(|(read, _)| read)
}

/// [`load`] with the file's meshes on its skeleton (a character): what the mesh reader said is
/// among the take's warnings.
pub fn load_character(
    path: &Path,
    options: &OpenOptions,
) -> Result<(Read, crate::model::mesh::Mesh), Error> {
    let file = read(path, options.max_size_or_default())?;
    let take = options.take.as_deref();
    let (read, mesh) = load_file(&file, &path.display().to_string(), take, true)?;
    Ok((read, mesh.unwrap_or_default()))
}

/// [`load`] of a GLB's or glTF's bytes alone (buffers inside it or in data: URIs), `name`
/// naming it in errors (the fuzz target's entry).
pub fn load_bytes(bytes: &[u8], name: &str, options: &OpenOptions) -> Result<Read, Error> {
    let file = parse(bytes, name, None, bytes.len() as u64)?;
    load_file(&file, name, options.take.as_deref(), false).map(|(read, _)| read)
}

/// [`load_character`] of a GLB's or glTF's bytes alone (the fuzz target's entry).
pub fn load_character_bytes(
    bytes: &[u8],
    name: &str,
    options: &OpenOptions,
) -> Result<(Read, crate::model::mesh::Mesh), Error> {
    let file = parse(bytes, name, None, bytes.len() as u64)?;
    let (read, mesh) = load_file(&file, name, options.take.as_deref(), true)?;
    Ok((read, mesh.unwrap_or_default()))
}

/// Reads the take (and with `with_mesh` the character's mesh) from a file already read: the node
/// tree, the take chosen, the skeleton picked out of the tree, then every frame baked.
fn load_file(
    file: &File,
    path: &str,
    take: Option<&str>,
    with_mesh: bool,
) -> Result<(Read, Option<crate::model::mesh::Mesh>), Error> {
    let document = &file.gltf.document;
    let count = document.nodes().len();
    let (parent, depth) = node_tree(document, path)?;
    let animations: Vec<gltf::Animation> = document.animations().collect();
    let names: Vec<String> = animations.iter().map(animation_name).collect();
    let mut warnings: Vec<Message> = Vec::new();
    let mut take_name = None;
    let chosen = if animations.is_empty() {
        if take.is_some() {
            pick_take(&names, take, path)?;
        }
        None
    } else {
        let (index, name) = choose_take(&names, take, path, &mut warnings)?;
        take_name = Some(name);
        Some(&animations[index])
    };
    let tracks = match chosen {
        Some(animation) => tracks(file, animation).map_err(|why| bad(path, why))?,
        None => Vec::new(),
    };
    let nodes: Vec<gltf::Node> = document.nodes().collect();
    let selected = selected_nodes(document, &nodes, &animations, &parent);
    let mut order: Vec<usize> = (0..count).filter(|&i| selected[i]).collect();
    if order.is_empty() {
        return Err(bad(
            path,
            "no skeleton: the file has no skin and no animated node",
        ));
    }
    order.sort_by_key(|&i| depth[i]);
    let mut skeleton_nodes = joint_nodes(&order, &parent, &nodes, path)?;
    warnings.extend(
        baked::unique_names(&mut skeleton_nodes)
            .into_iter()
            .map(Message::from),
    );
    let tree = Tree::new(parent, depth, order, &nodes);
    let mut cache: Vec<Option<DMat4>> = vec![None; count];
    let rest = tree.world_poses(&|n| tree.static_matrices[n], &mut cache);
    let timing = timing(&tracks);
    if let Some(warning) = &timing.warning {
        warnings.push(warning.clone().into());
    }
    let (skeleton, motion) = if tracks.is_empty() {
        warnings.push("no animation in the file: its rest pose, as one frame".into());
        baked::build_with(
            &skeleton_nodes,
            &rest,
            with_mesh,
            1,
            1.0 / timing.fps,
            |_, out| {
                out.extend_from_slice(&rest);
                Ok(())
            },
        )
    } else {
        let frame_count = frames_within(
            &timing,
            tree.order.len(),
            tree.posed_count(),
            tracks.len(),
            file.bytes,
        )
        .map_err(|why| bad(path, why))?;
        let take = Animated {
            tree: &tree,
            tracks: &tracks,
            timing: &timing,
            frame_count,
        };
        take.bake(&skeleton_nodes, &rest, with_mesh, cache)
    }
    .map_err(|e| match e {
        Error::Usage(message) if !message.starts_with(path) => Error::decoding(path, message),
        other => other,
    })?;
    // glTF is +Y up by its specification: read, never guessed.
    let skeleton = crate::model::skeleton::Skeleton {
        y_up_stated: true,
        ..skeleton
    };
    let mesh = if with_mesh {
        let (mesh, said) = character_mesh(file, path, &tree, &skeleton, &skeleton_nodes)?;
        warnings.extend(said.into_iter().map(Message::from));
        Some(mesh)
    } else {
        None
    };
    let read = Read {
        skeleton,
        motion,
        warnings,
        take: take_name,
        stated_units: None,
    };
    Ok((read, mesh))
}

/// Each node's parent and depth, refusing shared children, cycles, and a tree deeper than
/// [`crate::limits::MAX_DEPTH`].
fn node_tree(
    document: &gltf::Document,
    path: &str,
) -> Result<(Vec<Option<usize>>, Vec<usize>), Error> {
    let count = document.nodes().len();
    // Parents, refusing shared children and cycles.
    let mut parent = vec![None; count];
    for node in document.nodes() {
        for child in node.children() {
            let c = child.index();
            if parent[c].is_some() || c == node.index() {
                return Err(bad(path, format!("node {c} has more than one parent")));
            }
            parent[c] = Some(node.index());
        }
    }
    let mut depth = vec![0usize; count];
    for (i, d) in depth.iter_mut().enumerate() {
        let mut up = parent[i];
        while let Some(p) = up {
            *d += 1;
            if *d > count || *d > crate::limits::MAX_DEPTH {
                return Err(bad(path, "the node tree has a cycle or nests too deep"));
            }
            up = parent[p];
        }
    }
    Ok((parent, depth))
}

/// The nodes that make the skeleton: the skins' joints, else every node an animation moves
/// (else, in a file of bare nodes alone, the whole tree); with the nodes between them, and the
/// bare leaves under them as End Sites.
fn selected_nodes(
    document: &gltf::Document,
    nodes: &[gltf::Node],
    animations: &[gltf::Animation],
    parent: &[Option<usize>],
) -> Vec<bool> {
    let count = nodes.len();
    // The skeleton: skin joints, else every node any animation moves; and the nodes between.
    let mut seed = vec![false; count];
    for skin in document.skins() {
        for joint in skin.joints() {
            seed[joint.index()] = true;
        }
    }
    if !seed.iter().any(|&s| s) {
        for animation in animations {
            for channel in animation.channels() {
                if channel.target().property() != Property::MorphTargetWeights {
                    seed[channel.target().node().index()] = true;
                }
            }
        }
    }
    // No skin and no animation, and nothing but nodes (a rest pose as bvhview writes one, from a
    // take of 0 frames): the tree is the skeleton, its bare leaves End Sites (bvhview once
    // could not read back its own output).
    let bare = document.meshes().len() == 0 && document.cameras().len() == 0;
    if !seed.iter().any(|&s| s) && animations.is_empty() && bare {
        for node in nodes {
            seed[node.index()] = node.children().len() > 0 || parent[node.index()].is_none();
        }
    }
    let mut selected = seed.clone();
    for i in 0..count {
        if !seed[i] {
            continue;
        }
        let mut between = Vec::new();
        let mut up = parent[i];
        while let Some(p) = up {
            if seed[p] {
                for &b in &between {
                    selected[b] = true;
                }
                break;
            }
            between.push(p);
            up = parent[p];
        }
    }
    // A bare leaf under a joint (no mesh, no camera, no children: an end point, as bvhview's
    // own export writes a BVH's End Sites) joins as an End Site.
    for node in nodes {
        let i = node.index();
        if !selected[i]
            && parent[i].is_some_and(|p| selected[p])
            && node.children().len() == 0
            && node.mesh().is_none()
            && node.camera().is_none()
        {
            selected[i] = true;
        }
    }
    selected
}

/// The skeleton's joints, one per node of `order`: its name, and its parent the nearest
/// selected node above it.
fn joint_nodes(
    order: &[usize],
    parent: &[Option<usize>],
    nodes: &[gltf::Node],
    path: &str,
) -> Result<Vec<Node>, Error> {
    let mut position = vec![usize::MAX; nodes.len()];
    for (k, &i) in order.iter().enumerate() {
        position[i] = k;
    }
    order
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            let mut up = parent[i];
            let mut joint_parent = None;
            while let Some(p) = up {
                if position[p] != usize::MAX {
                    joint_parent = Some(position[p]);
                    break;
                }
                up = parent[p];
            }
            let name = nodes[i].name().unwrap_or("");
            Ok(Node {
                name: baked::joint_name(name, k).map_err(|why| bad(path, why))?,
                parent: joint_parent,
            })
        })
        .collect()
}

/// The file's node tree as the reader poses it: each node's parent and depth and its static
/// transform (as translation, rotation, scale and as the matrix the file gives), and the nodes
/// that became joints, parents first.
struct Tree {
    parent: Vec<Option<usize>>,
    depth: Vec<usize>,
    statics: Vec<Trs>,
    static_matrices: Vec<DMat4>,
    order: Vec<usize>,
}

impl Tree {
    /// The tree of `nodes`, with the joints in `order`.
    fn new(
        parent: Vec<Option<usize>>,
        depth: Vec<usize>,
        order: Vec<usize>,
        nodes: &[gltf::Node],
    ) -> Tree {
        let statics: Vec<Trs> = nodes
            .iter()
            .map(|node| {
                let (t, r, s) = node.transform().decomposed();
                let r = DQuat::from_xyzw(r[0] as f64, r[1] as f64, r[2] as f64, r[3] as f64);
                (
                    DVec3::from(t.map(|v| v as f64)),
                    unit(r),
                    DVec3::from(s.map(|v| v as f64)),
                )
            })
            .collect();
        let static_matrices: Vec<DMat4> = nodes
            .iter()
            .map(|node| {
                let m = node.transform().matrix();
                DMat4::from_cols_array_2d(&m.map(|c| c.map(|v| v as f64)))
            })
            .collect();
        Tree {
            parent,
            depth,
            statics,
            static_matrices,
            order,
        }
    }

    /// World matrices of the joints, from local matrices of all nodes. `cache` holds `None`
    /// for every node and is left so: only the nodes a call touches are cleared, so that a
    /// frame costs the posed nodes, not every node of the file (40,000 bare nodes × 4,000
    /// frames took 5 s).
    fn world_poses(
        &self,
        local: &dyn Fn(usize) -> DMat4,
        cache: &mut [Option<DMat4>],
    ) -> Vec<Pose> {
        let parent = &self.parent;
        let mut touched = Vec::new();
        let mut out = Vec::with_capacity(self.order.len());
        for &i in &self.order {
            let mut chain = Vec::new();
            let mut up = Some(i);
            while let Some(n) = up {
                if cache[n].is_some() {
                    break;
                }
                chain.push(n);
                up = parent[n];
            }
            for &n in chain.iter().rev() {
                let above = parent[n].and_then(|p| cache[p]).unwrap_or(DMat4::IDENTITY);
                cache[n] = Some(above * local(n));
                touched.push(n);
            }
            out.push(Pose::of_matrix(&cache[i].unwrap_or(DMat4::IDENTITY)));
        }
        for n in touched {
            cache[n] = None;
        }
        out
    }

    /// How many nodes each frame poses: the joints and every node above them.
    fn posed_count(&self) -> usize {
        let mut posed = vec![false; self.parent.len()];
        for &i in &self.order {
            let mut up = Some(i);
            while let Some(n) = up.filter(|&n| !posed[n]) {
                posed[n] = true;
                up = self.parent[n];
            }
        }
        posed.iter().filter(|&&p| p).count()
    }

    /// Every node's world matrix at rest.
    fn rest_world(&self) -> Vec<DMat4> {
        let count = self.parent.len();
        let mut rest_world: Vec<Option<DMat4>> = vec![None; count];
        let mut by_depth: Vec<usize> = (0..count).collect();
        by_depth.sort_by_key(|&i| self.depth[i]);
        for &n in &by_depth {
            let above = self.parent[n]
                .and_then(|p| rest_world[p])
                .unwrap_or(DMat4::IDENTITY);
            rest_world[n] = Some(above * self.static_matrices[n]);
        }
        rest_world
            .into_iter()
            .map(Option::unwrap_or_default)
            .collect()
    }
}

/// The chosen animation on the tree: its tracks, sampled at `timing`'s rate for `frame_count`
/// frames.
struct Animated<'a> {
    tree: &'a Tree,
    tracks: &'a [Track],
    timing: &'a Timing,
    frame_count: usize,
}

impl Animated<'_> {
    /// Every frame baked: each track sampled at the frame's time onto its node's static
    /// transform, then the joints' world matrices (`cache`: as [`Tree::world_poses`] takes it).
    fn bake(
        &self,
        skeleton_nodes: &[Node],
        rest: &[Pose],
        with_mesh: bool,
        mut cache: Vec<Option<DMat4>>,
    ) -> Result<
        (
            crate::model::skeleton::Skeleton,
            crate::model::motion::Motion,
        ),
        Error,
    > {
        let (tree, tracks) = (self.tree, self.tracks);
        let (start, fps) = (self.timing.start, self.timing.fps);
        let mut animated: Vec<Option<Trs>> = vec![None; tree.parent.len()];
        let mut sample = [0.0f64; 4];
        let mut hints = vec![0usize; tracks.len()];
        baked::build_with(
            skeleton_nodes,
            rest,
            with_mesh,
            self.frame_count,
            1.0 / fps,
            |f, out| {
                let time = start + f as f64 / fps;
                // Only the animated nodes were set (clearing every node cost nodes × frames).
                for track in tracks {
                    animated[track.node] = None;
                }
                for (track, hint) in tracks.iter().zip(hints.iter_mut()) {
                    let trs = animated[track.node].get_or_insert(tree.statics[track.node]);
                    track.sample(time, hint, &mut sample);
                    match track.property {
                        Property::Translation => {
                            trs.0 = DVec3::new(sample[0], sample[1], sample[2])
                        }
                        Property::Scale => trs.2 = DVec3::new(sample[0], sample[1], sample[2]),
                        Property::Rotation => {
                            trs.1 =
                                unit(DQuat::from_xyzw(sample[0], sample[1], sample[2], sample[3]))
                        }
                        Property::MorphTargetWeights => {}
                    }
                }
                out.extend(tree.world_poses(
                    &|n| match &animated[n] {
                        Some(trs) => trs_matrix(trs),
                        None => tree.static_matrices[n],
                    },
                    &mut cache,
                ));
                Ok(())
            },
        )
    }
}

/// The file's skinned meshes on the skeleton read: every node's world matrix at rest, and the
/// joint each selected node became (by name: the first joint of each).
fn character_mesh(
    file: &File,
    path: &str,
    tree: &Tree,
    skeleton: &crate::model::skeleton::Skeleton,
    skeleton_nodes: &[Node],
) -> Result<(crate::model::mesh::Mesh, Vec<String>), Error> {
    let rest_world = tree.rest_world();
    // The first joint of each name, looked up once a node (a search per node was
    // quadratic in a file of many nodes).
    let mut by_name = std::collections::HashMap::with_capacity(skeleton.joints.len());
    for (i, j) in skeleton.joints.iter().enumerate() {
        by_name.entry(j.name.as_str()).or_insert(i);
    }
    let mut joint = vec![None; tree.parent.len()];
    for (k, &n) in tree.order.iter().enumerate() {
        joint[n] = by_name.get(skeleton_nodes[k].name.as_str()).copied();
    }
    let frames = mesh::NodeFrames {
        parent: &tree.parent,
        rest: &rest_world,
        joint: &joint,
    };
    mesh::read(file, path, &frames)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gltf::read::file::base64;
    use crate::gltf::read::file::buffer_path;
    use gltf::animation::Interpolation;
    use std::rc::Rc;

    #[test]
    fn base64_decodes() {
        assert_eq!(base64("aGVsbG8=").unwrap(), b"hello");
        assert_eq!(base64("aGVsbG8").unwrap(), b"hello");
        assert!(base64("a$").is_none());
    }

    fn keyed(times: Vec<f32>) -> Track {
        let values = Rc::new(vec![0.0; 3 * times.len()]);
        Track {
            node: 0,
            property: Property::Translation,
            interpolation: Interpolation::Linear,
            times: Rc::new(times),
            values,
            width: 3,
        }
    }

    /// The rate is the key step that puts the most keys on a frame, snapped to a common rate;
    /// what does not fit is said; nothing is refused for a rate.
    #[test]
    fn the_rate_is_the_key_step_that_fits_the_most_keys() {
        let at = |rate: f32, n: usize| (0..n).map(|k| k as f32 / rate).collect::<Vec<f32>>();
        // Every frame of 30 fps: 30, no warning.
        let even = timing(&[keyed(at(30.0, 61))]);
        assert_eq!((even.fps, even.warning.is_none()), (30.0, true));
        // One odd key 1.5 ms after the last: still 30, said.
        let mut times = at(30.0, 31);
        times.push(1.0015);
        let odd = timing(&[keyed(times)]);
        assert_eq!(odd.fps, 30.0);
        assert!(odd.warning.unwrap().starts_with("1 of 32 key times"));
        // A track at 60 fps beside one at 30: every key is on a frame of 60.
        let both = timing(&[keyed(at(30.0, 61)), keyed(at(60.0, 121))]);
        assert_eq!((both.fps, both.warning.is_none()), (60.0, true));
        // Twenty tracks keyed at their ends only do not outvote one keyed at every frame.
        let mut tracks: Vec<Track> = (0..20).map(|_| keyed(vec![0.0, 2.0])).collect();
        tracks.push(keyed(at(30.0, 61)));
        assert_eq!(timing(&tracks).fps, 30.0);
        // Keys 0.5 ms apart: 1000 fps, said.
        let fast = timing(&[keyed((0..100).map(|k| k as f32 * 5e-4).collect())]);
        assert_eq!(fast.fps, 1000.0);
        assert!(
            fast.warning
                .unwrap()
                .contains("(2000 fps); sampled at 1000 fps")
        );
        // bvhview's own `Frame Time: 0.0083333` keys keep their step (not 1/120 s).
        let own = timing(&[keyed((0..200).map(|k| k as f32 * 0.0083333).collect())]);
        assert!((1.0 / own.fps - 0.0083333).abs() < 1e-9, "{}", own.fps);
    }

    #[test]
    fn buffer_paths_stay_in_the_folder() {
        let folder = std::env::temp_dir();
        for uri in [
            "/etc/passwd",
            "../x.bin",
            "http://host/x.bin",
            "a/../../x",
            "file:///x",
        ] {
            assert!(buffer_path(&folder, uri).is_err(), "{uri}");
        }
        // `./x.bin` is beside the file; an empty URI and a missing file say so.
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("x.bin"), [0u8; 4]).unwrap();
        assert!(buffer_path(dir.path(), "./x.bin").is_ok());
        let empty = buffer_path(dir.path(), "").unwrap_err();
        assert!(empty.contains("an empty URI names no file"), "{empty}");
        let missing = buffer_path(dir.path(), "y.bin").unwrap_err();
        assert_eq!(missing, "buffer 'y.bin': no such file beside the glTF");
    }
}
