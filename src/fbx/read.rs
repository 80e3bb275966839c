//! FBX (binary and ASCII, FBX 6 and 7) → the same `Skeleton` + `Motion` a BVH loads into.
//!
//! The file is read by ufbx, the C library Blender's own FBX importer (Blender ≥ 4.5) is built
//! on, with the options that importer uses, so that a take moves here as it does in Blender:
//!
//! - `space_conversion = AdjustTransforms`: the file's axes and unit are converted by adjusting
//!   the nodes' transforms (not by a root transform, not by changing geometry), as Blender does;
//! - `target_axes` = right-handed Y up (+X right, +Y up, +Z front): bvhview's world. Blender asks
//!   for its Z up (front −Y); the two differ by one fixed rotation, so the bones move the same;
//! - `target_unit_meters = 1`: lengths in metres, from the file's `UnitScaleFactor` (Mixamo's
//!   centimetres become metres), as Blender's importer at its default scale 1.0;
//! - `pivot_handling = AdjustToRotationPivot` and `geometry_transform_handling = HelperNodes`,
//!   `inherit_mode_handling = HelperNodes` (Blender's choices): rotation pivots become part of the
//!   node's translation, and what a bone cannot hold (geometric transforms, Maya's segment scale
//!   compensation) goes to helper nodes, which this reader skips when it picks joints: their
//!   effect is in the world matrices it reads. ufbx moves a node's attribute (its bone) onto
//!   the helper it makes for it, so a node is a bone when its helper holds one (`attribute`);
//! - a file that states no axes (FBX 5 and older) is read Z up, as Blender reads it
//!   (`unstated_axes_turn`);
//! - nothing else is read: geometry, embedded files and external files are ignored
//!   (`ignore_geometry`, `ignore_embedded`, `load_external_files = false`), so a file is only
//!   its nodes and curves.
//!
//! Limits (a hostile file gets an error, never takes the machine): ufbx's temporary and result
//! allocators are capped at 256 MiB + 64 bytes per byte of the file and at 16 M allocations plus
//! 16 per byte, nodes nest at most [`crate::limits::MAX_DEPTH`] deep, and a take has at most
//! `model::baked::MAX_FRAMES` frames. The file is read whole, so it is refused by its size on
//! disk past [`crate::limits::MAX_WHOLE_FILE_BYTES`] before a byte is read, and unless it is a
//! regular file. A take's range is its stack's (refused when it runs backwards), or its keys'
//! extent with a warning when the stack states none (see `stack_range`).
//!
//! The skeleton is the file's bones (`LimbNode`s) and the nodes between two of them; a file
//! without bones gives every animated node instead. Each frame of a take (an animation stack) is
//! evaluated by ufbx at the scene's own frame rate — every frame, not only at keys: the joints'
//! ancestors' local transforms multiplied down where that gives what ufbx's whole-scene
//! evaluation gives (checked at three frames), else the whole scene — and the world matrices go
//! through `model::baked`, which folds pre/post rotations, rest orientations
//! and scale into BVH channels that give the same world positions.

use super::matrix::matrix;
use super::records::BINARY_MAGIC;
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::baked::{self, Node, Pose};
use crate::model::reading::{Read, TakeInfo, choose_take, pick_take};
use crate::take::options::OpenOptions;
use glam::DMat4;
use std::path::Path;

fn allocator(bytes: usize) -> ufbx::AllocatorOpts {
    ufbx::AllocatorOpts {
        memory_limit: (256usize << 20).saturating_add(bytes.saturating_mul(64)),
        allocation_limit: (16usize << 20).saturating_add(bytes.saturating_mul(16)),
        ..Default::default()
    }
}

/// The load options (see the module's documentation for why each).
/// Blender's reading options; `geometry`: meshes and skins read too (a character).
fn load_options<'a>(bytes: usize, geometry: bool) -> ufbx::LoadOpts<'a> {
    ufbx::LoadOpts {
        temp_allocator: allocator(bytes),
        result_allocator: allocator(bytes),
        ignore_geometry: !geometry,
        ignore_embedded: true,
        load_external_files: false,
        evaluate_skinning: false,
        evaluate_caches: false,
        file_format: ufbx::FileFormat::Fbx,
        node_depth_limit: crate::limits::MAX_DEPTH as u32,
        space_conversion: ufbx::SpaceConversion::AdjustTransforms,
        target_axes: ufbx::CoordinateAxes {
            right: ufbx::CoordinateAxis::PositiveX,
            up: ufbx::CoordinateAxis::PositiveY,
            front: ufbx::CoordinateAxis::PositiveZ,
        },
        target_unit_meters: 1.0,
        pivot_handling: ufbx::PivotHandling::AdjustToRotationPivot,
        geometry_transform_handling: ufbx::GeometryTransformHandling::HelperNodes,
        inherit_mode_handling: ufbx::InheritModeHandling::HelperNodes,
        ..Default::default()
    }
}

fn ufbx_error(name: &str, error: &ufbx::Error) -> Error {
    use ufbx::ErrorType as E;
    let what = match error.type_ {
        E::TruncatedFile => "the file is truncated".to_string(),
        E::EmptyFile => "the file is empty".to_string(),
        E::UnrecognizedFileFormat => "not an FBX file".to_string(),
        E::MemoryLimit | E::AllocationLimit | E::OutOfMemory => {
            "the file asks for more memory than its size allows (damaged or hostile)".to_string()
        }
        E::NodeDepthLimit => format!("nodes nest deeper than {} levels", crate::limits::MAX_DEPTH),
        E::UnsupportedVersion => "an FBX version ufbx does not read".to_string(),
        _ => {
            let text: &str = &error.description;
            let text = text.trim();
            if text.is_empty() {
                format!("ufbx cannot read it ({:?})", error.type_)
            } else {
                format!("damaged FBX ({text})")
            }
        }
    };
    Error::decoding(name, what)
}

fn read_scene(bytes: &[u8], name: &str, geometry: bool) -> Result<ufbx::SceneRoot, Error> {
    if let Some(why) = not_fbx(bytes) {
        return Err(Error::decoding(name, format!("not an FBX file: {why}")));
    }
    ufbx::load_memory(bytes, load_options(bytes.len(), geometry)).map_err(|e| {
        match (e.type_, super::records::first_fault(bytes)) {
            // ufbx says only "Failed to load" of a damaged binary file: say where.
            (ufbx::ErrorType::Unknown, Some(fault)) => {
                Error::decoding(name, format!("damaged FBX: {fault}"))
            }
            _ => ufbx_error(name, &e),
        }
    })
}

/// Why `bytes` are neither a binary FBX nor FBX text, if they are not: a binary file starts
/// with [`BINARY_MAGIC`]; FBX text is `Key: value` lines after `;` comments. Nothing of the file
/// is quoted (it may be anything).
fn not_fbx(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(BINARY_MAGIC) {
        return None;
    }
    let Ok(text) = std::str::from_utf8(&bytes[..bytes.len().min(4096)])
        .or_else(|e| std::str::from_utf8(&bytes[..e.valid_up_to()]).map_err(|_| ()))
    else {
        return Some("binary data without FBX's header");
    };
    if text.contains('\0') {
        return Some("binary data without FBX's header");
    }
    let first = text
        .lines()
        .map(str::trim)
        .find(|line| !line.is_empty() && !line.starts_with(';'));
    match first {
        // Only comments so far (or nothing): ufbx says what is missing.
        None => None,
        Some(line) => {
            let key = line.split(':').next().unwrap_or("");
            let is_key = line.contains(':')
                && !key.is_empty()
                && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            (!is_key).then_some("text, but not FBX's `Key: value` lines")
        }
    }
}

fn fps(scene: &ufbx::Scene) -> f64 {
    let fps = scene.settings.frames_per_second;
    if fps.is_finite() && fps > 0.0 {
        fps
    } else {
        30.0
    }
}

/// A take's time range in seconds, and what is said about it.
///
/// It is the stack's `LocalStart`..`LocalStop` (else `ReferenceStart`..`ReferenceStop`, else
/// the `Takes` section's `LocalTime`, as ufbx reads them). A range that runs backwards (start
/// after stop) is refused: nothing says which end is meant. A stack that states no range at all
/// is read over the extent of its keys (the first key of any of its curves to the last), and a
/// warning says so; without keys, it is one frame at 0.
fn stack_range(stack: &ufbx::AnimStack) -> Result<(f64, f64, Option<String>), String> {
    let name = crate::limits::quoted(&stack.element.name);
    let stated = stack.element.props.props.iter().any(|p| {
        let name: &str = &p.name;
        matches!(
            name,
            "LocalStart" | "LocalStop" | "ReferenceStart" | "ReferenceStop"
        )
    });
    if stated {
        let (begin, end) = (stack.time_begin, stack.time_end);
        if !(begin.is_finite() && end.is_finite()) {
            return Err(format!("take '{name}': a time range that is not finite"));
        }
        if end < begin {
            return Err(format!(
                "take '{name}': its time range runs backwards (LocalStart {} s is after \
                 LocalStop {} s)",
                crate::limits::brief(begin),
                crate::limits::brief(end)
            ));
        }
        return Ok((begin, end, None));
    }
    let (mut first, mut last) = (f64::MAX, f64::MIN);
    for layer in stack.layers.iter() {
        for value in layer.anim_values.iter() {
            for curve in value.curves.iter().flatten() {
                let keys = &curve.keyframes;
                if let (Some(a), Some(b)) = (keys.first(), keys.last())
                    && a.time.is_finite()
                    && b.time.is_finite()
                {
                    first = first.min(a.time.min(b.time));
                    last = last.max(a.time.max(b.time));
                }
            }
        }
    }
    if first > last {
        return Ok((
            0.0,
            0.0,
            Some(format!(
                "take '{name}' states no time range and has no keys: one frame at 0 s"
            )),
        ));
    }
    Ok((
        first,
        last,
        Some(format!(
            "take '{name}' states no time range (no LocalStart or LocalStop): read over its \
             keys, {} s to {} s",
            crate::limits::brief(first),
            crate::limits::brief(last)
        )),
    ))
}

/// The takes of an FBX file (its animation stacks), in file order.
pub fn takes(path: &Path, max_size: u64) -> Result<Vec<TakeInfo>, Error> {
    let bytes = crate::io::whole::read_binary_file(path, max_size)?;
    takes_of_bytes(&bytes, &path.display().to_string())
}

/// [`takes`] of a file's bytes, `name` naming it in errors.
pub fn takes_of_bytes(bytes: &[u8], name: &str) -> Result<Vec<TakeInfo>, Error> {
    let scene = read_scene(bytes, name, false)?;
    let fps = fps(&scene);
    scene
        .anim_stacks
        .iter()
        .map(|stack| {
            let (begin, end, _) = stack_range(stack).map_err(|why| Error::decoding(name, why))?;
            let frames =
                baked::frame_count(begin, end, fps, 1).map_err(|why| Error::decoding(name, why))?;
            Ok(TakeInfo {
                name: stack.element.name.to_string(),
                frames,
                frame_time: 1.0 / fps,
            })
        })
        .collect()
}

fn is_helper(node: &ufbx::Node) -> bool {
    node.is_scale_helper || node.is_geometry_transform_helper
}

/// What the file's node is (a bone, a camera, …). Where ufbx makes a helper for a node (Maya's
/// segment scale compensation, HumanIK rigs, geometric transforms), it moves the node's
/// attribute onto the helper: the node's kind is then its helper's (the helpers were once
/// read as the bones, named `node<k>`, and the file's bones were lost).
fn attribute(node: &ufbx::Node) -> ufbx::ElementType {
    let helpers = [&node.scale_helper, &node.geometry_transform_helper];
    match (node.attrib_type, helpers.into_iter().flatten().next()) {
        (ufbx::ElementType::Unknown, Some(helper)) => helper.attrib_type,
        (kind, _) => kind,
    }
}

/// A camera, a light or a camera switcher (MotionBuilder's Producer cameras among them) is
/// never a joint, animated or not (a scene without LimbNodes once read its cameras as the
/// skeleton).
fn is_scenery(node: &ufbx::Node) -> bool {
    use ufbx::ElementType::{Camera, CameraSwitcher, Light, StereoCamera};
    matches!(
        attribute(node),
        Camera | StereoCamera | CameraSwitcher | Light
    )
}

/// The scene's nodes that make the skeleton, as indices into `scene.nodes`, parents first, with
/// the parent of each among them. `skin_bones`: the nodes a skin's clusters name are joints too
/// (a character's mesh may be bound to nodes that are not marked as bones).
fn skeleton_nodes(scene: &ufbx::Scene, skin_bones: bool) -> (Vec<usize>, Vec<Option<usize>>, bool) {
    let count = scene.nodes.len();
    let mut seed = vec![false; count];
    let mut bones = false;
    if skin_bones {
        for skin in scene.skin_deformers.iter() {
            for cluster in skin.clusters.iter() {
                if let Some(node) = cluster.bone_node.as_ref() {
                    let i = node.element.typed_id as usize;
                    if i < count && !node.is_root {
                        seed[i] = true;
                        bones = true;
                    }
                }
            }
        }
    }
    for (i, node) in scene.nodes.iter().enumerate() {
        if attribute(node) == ufbx::ElementType::Bone && !node.is_root && !is_helper(node) {
            seed[i] = true;
            bones = true;
        }
    }
    let mut animated = false;
    if !bones {
        for layer in scene.anim_layers.iter() {
            for prop in layer.anim_props.iter() {
                let element = &prop.element;
                if element.type_ == ufbx::ElementType::Node {
                    let i = element.typed_id as usize;
                    let joint = scene
                        .nodes
                        .get(i)
                        .filter(|node| !node.is_root && !is_helper(node) && !is_scenery(node));
                    if joint.is_some() {
                        seed[i] = true;
                        animated = true;
                    }
                }
            }
        }
    }
    if !bones && !animated {
        // Neither bones nor motion: every node stands as it is (a rest pose).
        for (i, node) in scene.nodes.iter().enumerate() {
            seed[i] = !node.is_root && !is_helper(node) && !is_scenery(node);
        }
    }
    // Nodes strictly between two seeds join them (the transforms between bones).
    let mut selected = seed.clone();
    for i in 0..count {
        if !seed[i] {
            continue;
        }
        let mut path = Vec::new();
        let mut up = scene.nodes[i]
            .parent
            .as_ref()
            .map(|p| p.element.typed_id as usize);
        while let Some(p) = up.filter(|&p| p < count) {
            if seed[p] {
                for &between in &path {
                    selected[between] = true;
                }
                break;
            }
            let node = &scene.nodes[p];
            if node.is_root {
                break;
            }
            if !is_helper(node) {
                path.push(p);
            }
            up = node.parent.as_ref().map(|q| q.element.typed_id as usize);
        }
    }
    let mut order: Vec<usize> = (0..count).filter(|&i| selected[i]).collect();
    order.sort_by_key(|&i| scene.nodes[i].node_depth);
    let mut position = vec![usize::MAX; count];
    for (k, &i) in order.iter().enumerate() {
        position[i] = k;
    }
    let parents = order
        .iter()
        .map(|&i| {
            let mut up = scene.nodes[i]
                .parent
                .as_ref()
                .map(|p| p.element.typed_id as usize);
            while let Some(p) = up.filter(|&p| p < count) {
                if position[p] != usize::MAX {
                    return Some(position[p]);
                }
                up = scene.nodes[p]
                    .parent
                    .as_ref()
                    .map(|q| q.element.typed_id as usize);
            }
            None
        })
        .collect();
    (order, parents, bones)
}

/// Every node above and at the joints (the scene's root left out), parents first.
fn ancestors(scene: &ufbx::Scene, order: &[usize]) -> Vec<usize> {
    let count = scene.nodes.len();
    let mut wanted = vec![false; count];
    for &i in order {
        let mut up = Some(i);
        while let Some(n) = up.filter(|&n| n < count && !wanted[n]) {
            if scene.nodes[n].is_root {
                break;
            }
            wanted[n] = true;
            up = scene.nodes[n]
                .parent
                .as_ref()
                .map(|p| p.element.typed_id as usize);
        }
    }
    let mut chain: Vec<usize> = (0..count).filter(|&n| wanted[n]).collect();
    chain.sort_by_key(|&n| scene.nodes[n].node_depth);
    chain
}

/// The turn from a file's own coordinates to bvhview's Y up where the file states no axes (FBX 5
/// and older have no `GlobalSettings`), else the identity (ufbx has turned the scene already).
/// ufbx leaves such a scene as it is; Blender's importer (ufbx with Blender's Z up) then shows
/// the coordinates as Z up, and the files of that time (3ds Max, MotionBuilder 5) were Z up, so
/// bvhview reads them as Blender does: Z up, front −Y, turned to Y up, front +Z.
fn unstated_axes_turn(scene: &ufbx::Scene) -> DMat4 {
    if scene.settings.axes.up == ufbx::CoordinateAxis::Unknown {
        DMat4::from_rotation_x(-std::f64::consts::FRAC_PI_2)
    } else {
        DMat4::IDENTITY
    }
}

/// The joints' world poses at `time` from their ancestors' local transforms.
fn quick_poses(
    scene: &ufbx::Scene,
    anim: &ufbx::Anim,
    chain: &[usize],
    order: &[usize],
    time: f64,
) -> Vec<Pose> {
    let count = scene.nodes.len();
    let mut world: Vec<Option<DMat4>> = vec![None; count];
    for &n in chain {
        let node = &scene.nodes[n];
        let local = matrix(&ufbx::transform_to_matrix(&ufbx::evaluate_transform(
            anim, node, time,
        )));
        let above = node
            .parent
            .as_ref()
            .map(|p| p.element.typed_id as usize)
            .filter(|&p| p < count)
            .map(|p| world[p].unwrap_or_else(|| matrix(&scene.nodes[p].node_to_world)))
            .unwrap_or(DMat4::IDENTITY);
        world[n] = Some(above * local);
    }
    let turn = unstated_axes_turn(scene);
    order
        .iter()
        .map(|&i| Pose::of_matrix(&(turn * world[i].unwrap_or(DMat4::IDENTITY))))
        .collect()
}

/// Reads the FBX file at `path` with `options` (its take, size limit and threads; the first
/// take unless [`OpenOptions::take`] names another, by name or index).
pub fn load(path: &Path, options: &OpenOptions) -> Result<Read, Error> {
    let bytes = crate::io::whole::read_binary_file(path, options.max_size_or_default())?;
    load_bytes(&bytes, &path.display().to_string(), options)
}

/// [`load`] of a file's bytes, `name` naming it in errors (the fuzz target's entry).
pub fn load_bytes(bytes: &[u8], name: &str, options: &OpenOptions) -> Result<Read, Error> {
    let (take, threads) = (options.take.as_deref(), options.threads_or_cores());
    let scene = read_scene(bytes, name, false)?;
    let how = How {
        threads,
        skin_bones: false,
        exact: true,
    };
    load_scene(&scene, bytes.len(), name, take, how).map(|(read, _)| read)
}

/// How a scene's take is read: on how many threads, whether the nodes a skin is bound to are
/// joints (a character), and whether a plain take is read exactly (its own channels and units).
#[derive(Clone, Copy)]
struct How {
    threads: usize,
    skin_bones: bool,
    exact: bool,
}

/// [`load_bytes`] the baked way always: every frame evaluated by ufbx and baked into ZYX
/// channels in metres, even where the take is plain and [`load_bytes`] reads its own channels
/// in its own units (see the `plain` module). What the test that proves the two equal reads.
pub fn load_bytes_baked(bytes: &[u8], name: &str, options: &OpenOptions) -> Result<Read, Error> {
    let (take, threads) = (options.take.as_deref(), options.threads_or_cores());
    let scene = read_scene(bytes, name, false)?;
    let how = How {
        threads,
        skin_bones: false,
        exact: false,
    };
    load_scene(&scene, bytes.len(), name, take, how).map(|(read, _)| read)
}

/// [`load`] with the file's meshes on its skeleton (a character), the nodes its skins are bound
/// to among the joints: what the mesh reader said is among the take's warnings.
pub fn load_character(
    path: &Path,
    options: &OpenOptions,
) -> Result<(Read, crate::model::mesh::Mesh), Error> {
    let bytes = crate::io::whole::read_binary_file(path, options.max_size_or_default())?;
    load_character_bytes(&bytes, &path.display().to_string(), options)
}

/// [`load_character`] of a file's bytes (the fuzz target's entry).
pub fn load_character_bytes(
    bytes: &[u8],
    name: &str,
    options: &OpenOptions,
) -> Result<(Read, crate::model::mesh::Mesh), Error> {
    let (take, threads) = (options.take.as_deref(), options.threads_or_cores());
    let scene = read_scene(bytes, name, true)?;
    // A character is baked always: its mesh is bound to its rest pose, made each joint's zero.
    let how = How {
        threads,
        skin_bones: true,
        exact: false,
    };
    let (mut read, joint) = load_scene(&scene, bytes.len(), name, take, how)?;
    let turn = unstated_axes_turn(&scene);
    let (mesh, said) = super::mesh::read(&scene, name, bytes.len() as u64, &joint, turn)?;
    read.warnings.extend(said.into_iter().map(Message::from));
    Ok((read, mesh))
}

/// The take of a scene read, and the skeleton joint each scene node became.
fn load_scene(
    scene: &ufbx::SceneRoot,
    bytes_len: usize,
    name: &str,
    take: Option<&str>,
    how: How,
) -> Result<(Read, Vec<Option<usize>>), Error> {
    let (mut read, order, nodes) = load_nodes(scene, bytes_len, name, take, how)?;
    // A header that states the axes was turned to +Y up by ufbx: read, never guessed. A file
    // that states none (FBX 5) is read Z up by convention, which the motion may overrule.
    read.skeleton.y_up_stated = scene.settings.axes.up != ufbx::CoordinateAxis::Unknown;
    let index: std::collections::HashMap<&str, usize> = read
        .skeleton
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| (joint.name.as_str(), j))
        .collect();
    let mut joint = vec![None; scene.nodes.len()];
    for (&n, node) in order.iter().zip(&nodes) {
        joint[n] = index.get(node.name.as_str()).copied();
    }
    Ok((read, joint))
}

/// The take of a scene, the scene nodes it was made of and the joints they became.
fn load_nodes(
    scene: &ufbx::SceneRoot,
    bytes_len: usize,
    name: &str,
    take: Option<&str>,
    how: How,
) -> Result<(Read, Vec<usize>, Vec<Node>), Error> {
    let (threads, skin_bones) = (how.threads.max(1), how.skin_bones);
    let path = name;
    let bad = |why: String| Error::decoding(name, why);
    let (order, parents, _bones) = skeleton_nodes(scene, skin_bones);
    if order.is_empty() {
        return Err(bad(
            "no skeleton: the file has no node (no bone, no animated node, nothing to stand)"
                .into(),
        ));
    }
    let mut nodes = order
        .iter()
        .zip(&parents)
        .enumerate()
        .map(|(k, (&i, &parent))| {
            Ok(Node {
                name: baked::joint_name(&scene.nodes[i].element.name, k).map_err(&bad)?,
                parent,
            })
        })
        .collect::<Result<Vec<Node>, Error>>()?;
    let renamed = baked::unique_names(&mut nodes);
    let turn = unstated_axes_turn(scene);
    let rest: Vec<Pose> = order
        .iter()
        .map(|&i| Pose::of_matrix(&(turn * matrix(&scene.nodes[i].node_to_world))))
        .collect();
    let fps = fps(scene);
    let mut warnings: Vec<Message> = renamed.into_iter().map(Message::from).collect();
    if turn != DMat4::IDENTITY {
        warnings.push(
            "the file states no axes (FBX 5 and older): read as Z up, as Blender reads it".into(),
        );
    }
    let names: Vec<String> = scene
        .anim_stacks
        .iter()
        .map(|s| s.element.name.to_string())
        .collect();
    let baking = Baking {
        scene,
        name,
        bytes_len,
        threads,
        skin_bones,
        order: &order,
        nodes: &nodes,
        rest: &rest,
        turn,
        fps,
        exact: how.exact && !skin_bones && turn == DMat4::IDENTITY,
    };
    let mut chosen: Option<String> = None;
    let mut stated_units = None;
    let (skeleton, motion) = if scene.anim_stacks.is_empty() {
        if take.is_some() {
            pick_take(&names, take, path)?;
        }
        warnings.push("no animation in the file: its rest pose, as one frame".into());
        baked::build_with(&nodes, &rest, skin_bones, 1, 1.0 / fps, |_, out| {
            out.extend_from_slice(&rest);
            Ok(())
        })
        .map_err(|e| baking.named(e))?
    } else {
        let (index, stack_name) = choose_take(&names, take, path, &mut warnings)?;
        chosen = Some(stack_name);
        let (skeleton, motion, units) = baking.stack(index, &mut warnings)?;
        stated_units = units;
        (skeleton, motion)
    };
    let read = Read {
        skeleton,
        motion,
        warnings,
        take: chosen,
        stated_units,
    };
    Ok((read, order, nodes))
}

/// What baking a scene's take needs: the scene and its file (name, size), the threads to
/// evaluate on, the joints (`order`: the scene nodes they are, `nodes`: their names and
/// parents, `rest`: their rest pose), the turn of a file that states no axes, the rate, and
/// whether a plain take may be read exactly. Only the scene root (`Sync`) and numbers go to the threads: ufbx's element types are not.
struct Baking<'a> {
    scene: &'a ufbx::SceneRoot,
    name: &'a str,
    bytes_len: usize,
    threads: usize,
    skin_bones: bool,
    order: &'a [usize],
    nodes: &'a [Node],
    rest: &'a [Pose],
    turn: DMat4,
    fps: f64,
    exact: bool,
}

/// A take read: its skeleton, its motion, and the units they are in where the file states them
/// (a plain take read exactly; `None`: metres, baked).
type Taken = (
    crate::model::skeleton::Skeleton,
    crate::model::motion::Motion,
    Option<crate::model::stance::Units>,
);

impl Baking<'_> {
    /// An error of the file, named.
    fn bad(&self, why: String) -> Error {
        Error::decoding(self.name, why)
    }

    /// An error of the baking (the file's transforms), named by the file.
    fn named(&self, error: Error) -> Error {
        match error {
            Error::Usage(message) if !message.starts_with(self.name) => {
                self.bad(message.to_string())
            }
            other => other,
        }
    }

    /// Every frame of the take of anim stack `index`: a plain take's own channels where they
    /// agree with the whole scene's evaluation at the first, middle and last frames (see the
    /// `plain` module), else baked: the quick way where it agrees so, else the whole scene
    /// evaluated in each frame on the threads. What the stack's range says goes to `warnings`.
    fn stack(&self, index: usize, warnings: &mut Vec<Message>) -> Result<Taken, Error> {
        let (scene, order, fps) = (self.scene, self.order, self.fps);
        let stack = &scene.anim_stacks[index];
        let (begin, end, said) = stack_range(stack).map_err(|why| self.bad(why))?;
        warnings.extend(said.into_iter().map(Message::from));
        let count =
            baked::frame_count(begin, end, fps, order.len()).map_err(|why| self.bad(why))?;
        // Each frame is evaluated: the take's frames × (nodes evaluated + animated values of
        // every layer) are held to the file's size, as a glTF's are (a 16 KB file whose range
        // says nine hours asked for 960,000 frames; a 568 KB file of 40 layers for 40,000 s took
        // 16 s, each frame blending every layer's curves). The nodes are the joints' ancestors
        // on the quick way, every node of the scene on the whole scene's evaluation (checked
        // again before it is taken).
        let chains = ancestors(scene, order);
        let values: usize = stack.layers.iter().map(|l| l.anim_values.len()).sum();
        let span = Span { begin, end, count };
        self.within(index, &span, values, chains.len())?;
        if let Some(taken) = self.exactly(index, begin, count)? {
            return Ok(taken);
        }
        // The quick way: each node's local transform (ufbx's `evaluate_transform`, adjustments
        // included) multiplied down from the root, for the joints' ancestors only. Used when it
        // gives what the whole scene's evaluation gives at the first, middle and last frames
        // (it would not where ufbx keeps a node's inheritance its own way).
        let quick = |f: usize| -> Vec<Pose> {
            let time = begin + f as f64 / fps;
            quick_poses(scene, &stack.anim, &chains, order, time)
        };
        let mut fast = true;
        for f in [0, count / 2, count - 1] {
            if !same_poses(&quick(f), &self.evaluate(index, begin, f)?) {
                fast = false;
                break;
            }
        }
        let baked = |(skeleton, motion)| (skeleton, motion, None);
        if fast {
            return baked::build_with(
                self.nodes,
                self.rest,
                self.skin_bones,
                count,
                1.0 / fps,
                |f, out| {
                    out.extend(quick(f));
                    Ok(())
                },
            )
            .map(baked)
            .map_err(|e| self.named(e));
        }
        // The whole scene is evaluated in each frame: its every node counts.
        self.within(index, &span, values, scene.nodes.len())?;
        self.evaluated_on_threads(index, begin, count)
            .map(baked)
            .map_err(|e| self.named(e))
    }

    /// The take of anim stack `index` read exactly, in the file's units, where it is plain and
    /// that reading gives the whole scene's evaluation at the first, middle and last frames' keys:
    /// world places (in metres) within a millionth of the figure's size, world rotations within
    /// 1e-9 of the same.
    fn exactly(&self, index: usize, begin: f64, count: usize) -> Result<Option<Taken>, Error> {
        let scene = self.scene;
        let metres = scene.settings.original_unit_meters;
        if !(self.exact && metres.is_finite() && metres > 0.0) {
            return Ok(None);
        }
        let stack = &scene.anim_stacks[index];
        let Some(plain) = super::plain::read(
            scene,
            stack,
            self.order,
            self.nodes,
            (begin, count, self.fps),
        ) else {
            return Ok(None);
        };
        let mut world = Vec::new();
        for f in [0, count / 2, count - 1] {
            // At the keys' own time: a key a fraction of a tick off the frame's time is the
            // key, and the curve between two keys a fraction of a tick away is not compared.
            let truth = self.evaluate_at(index, plain.times[f])?;
            let size = truth
                .iter()
                .map(|p| p.position.abs().max_element())
                .fold(1e-9, f64::max);
            crate::model::pose::world_transforms_f64(
                &plain.skeleton,
                plain.motion.frame(f),
                crate::model::pose::OffsetMode::Replace,
                &mut world,
            );
            let agrees = world
                .iter()
                .zip(&plain.to_node)
                .all(|((rotation, at), &k)| {
                    let want = &truth[k];
                    (*at * metres - want.position).abs().max_element() <= 1e-6 * size
                        && rotation.dot(want.rotation).abs() >= 1.0 - 1e-9
                });
            if !agrees {
                return Ok(None);
            }
        }
        let units = crate::model::stance::Units::of_metres(metres as f32);
        Ok(Some((plain.skeleton, plain.motion, Some(units))))
    }

    /// Refuses a take whose frames × (nodes evaluated + animated values) exceed what a file
    /// of its size is read for.
    fn within(&self, index: usize, span: &Span, values: usize, nodes: usize) -> Result<(), Error> {
        let stack = &self.scene.anim_stacks[index];
        let (order, count) = (self.order, span.count);
        let budget = baked::frame_work_budget(self.bytes_len as u64);
        let nodes = nodes.max(order.len());
        let work = (nodes as u64).saturating_add(values as u64);
        if (count as u64).saturating_mul(work) <= budget {
            return Ok(());
        }
        let evaluated = format!(
            "{} evaluated, {} in {}",
            crate::io::error::counted(nodes, "node"),
            crate::io::error::counted(values, "animated value"),
            crate::io::error::counted(stack.layers.len(), "layer")
        );
        Err(self.bad(format!(
            "take '{}' lasts {} s at {} fps: {} of {} ({evaluated}), more than a file of {} \
             bytes is read for (frames × (nodes evaluated + animated values) at most \
             {budget}, {} a byte); refused as damaged or hostile",
            crate::limits::quoted(&stack.element.name),
            crate::limits::brief(span.end - span.begin),
            crate::limits::brief(self.fps),
            crate::io::error::counted(count, "frame"),
            crate::io::error::counted(order.len(), "joint"),
            self.bytes_len,
            baked::FRAME_WORK_PER_BYTE
        )))
    }

    /// One frame: the whole scene evaluated by ufbx at its time, the joints' world matrices.
    fn evaluate(&self, index: usize, begin: f64, f: usize) -> Result<Vec<Pose>, Error> {
        self.evaluate_at(index, begin + f as f64 / self.fps)
    }

    /// The whole scene evaluated by ufbx at `time`, the joints' world matrices.
    fn evaluate_at(&self, index: usize, time: f64) -> Result<Vec<Pose>, Error> {
        let root = self.scene;
        let stack = &root.anim_stacks[index];
        let options = ufbx::EvaluateOpts {
            temp_allocator: allocator(self.bytes_len),
            result_allocator: allocator(self.bytes_len),
            evaluate_skinning: false,
            evaluate_caches: false,
            load_external_files: false,
            ..Default::default()
        };
        let evaluated = ufbx::evaluate_scene(root, &stack.anim, time, options)
            .map_err(|e| ufbx_error(self.name, &e))?;
        Ok(self
            .order
            .iter()
            .map(|&i| Pose::of_matrix(&(self.turn * matrix(&evaluated.nodes[i].node_to_world))))
            .collect())
    }

    /// Every frame with the whole scene evaluated: on the threads, BLOCK frames at a time,
    /// handed over in order.
    fn evaluated_on_threads(
        &self,
        index: usize,
        begin: f64,
        count: usize,
    ) -> Result<
        (
            crate::model::skeleton::Skeleton,
            crate::model::motion::Motion,
        ),
        Error,
    > {
        const BLOCK: usize = 256;
        let threads = self.threads;
        let mut ready: std::collections::VecDeque<Vec<Pose>> = Default::default();
        let mut next = 0;
        baked::build_with(
            self.nodes,
            self.rest,
            self.skin_bones,
            count,
            1.0 / self.fps,
            |f, out| {
                if ready.is_empty() {
                    let block = BLOCK.min(count - next);
                    let mut results: Vec<Result<Vec<Pose>, Error>> = Vec::with_capacity(block);
                    crate::io::parallel::map_in_order(
                        block,
                        threads,
                        2 * threads.max(1),
                        |k| self.evaluate(index, begin, next + k),
                        |_, result| {
                            let ok = result.is_ok();
                            results.push(result);
                            ok
                        },
                    );
                    for result in results {
                        ready.push_back(result?);
                    }
                    next += block;
                }
                debug_assert_eq!(f + ready.len(), next);
                out.extend(ready.pop_front().unwrap_or_default());
                Ok(())
            },
        )
    }
}

/// A take's time range, and the frames it holds at the scene's rate.
struct Span {
    begin: f64,
    end: f64,
    count: usize,
}

/// Whether the quick way's poses are the whole scene's: places within a billionth of their
/// size, rotations within 1e-12 of the same.
fn same_poses(a: &[Pose], b: &[Pose]) -> bool {
    a.iter().zip(b).all(|(p, q)| {
        let size = 1.0 + p.position.abs().max_element();
        (p.position - q.position).abs().max_element() <= 1e-9 * size
            && p.rotation.dot(q.rotation).abs() >= 1.0 - 1e-12
    })
}
