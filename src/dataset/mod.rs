//! `bvhview dataset`: every take under a folder turned into training arrays, on every core.
//!
//! One take is one unit of work ([`compile_take`]): loaded, turned to Y up and metres by its
//! guessed [`Stance`](crate::model::stance::Stance), resampled to one frame rate, then its world
//! positions, local rotations, root translations, velocities and foot contacts computed. A take
//! that fails is skipped and reported with its `path:line:column`. [`store`] writes the clips,
//! grouped by skeleton topology, as `manifest.json` plus one `.npy` file per array; it also
//! merges datasets compiled in pieces (on a cluster's workers) into the one a single process
//! would have written, byte for byte.

pub mod humanml3d;
pub mod merge;
pub mod quaternions;
pub mod read;
pub mod rebuild;
#[doc(hidden)] // the writer behind `compile`; its manifest types, for the tests
pub mod store;

use crate::info::batch::Item;
use crate::io::error::Error;
use crate::io::message::Message;
use crate::model::pose::{self, FkPlan, FkScratch, OffsetMode, RotationKind, Up};
use glam::Vec3;
use std::path::{Path, PathBuf};

mod clip;
mod continuity;
mod feet;
mod floor;
mod folder;
mod join;
mod manifest;
mod options;
mod steps;
mod summary;

pub use clip::{About, Clip, ClipMetrics, Skipped, Source, Topology};
use continuity::continuous_quaternions;
use feet::feet_of;
pub use feet::guess_feet;
use floor::{contacts, ground};
pub use options::{FeatureSet, Options};
pub use steps::Stages;
use steps::{Posed, Prepared, topology_of};
pub use summary::Summary;

/// Every take under `dir` in path order: BVH files and ASF/AMC pairs (an AMC without a skeleton
/// and an ASF without motion are listed too, and skipped with a reason). A folder without any
/// is refused: there is no dataset to make of it. What the walk left out is dropped here;
/// [`walk`] keeps it.
pub fn takes(dir: &Path) -> Result<Vec<Item>, Error> {
    walk(dir).map(|walk| walk.items)
}

/// [`takes`], and what the folder walk skipped ([`crate::info::batch::collect_takes`]).
pub fn walk(dir: &Path) -> Result<crate::info::batch::Walk, Error> {
    crate::info::batch::collect_takes(dir)
}

/// Compiles one take found under `dir` (the folder its manifest path is relative to): its
/// rotations go from the file's channels to quaternions once, and every array is made from them
/// (the `quaternions` module). The same clip as [`compile_take_plain`], which edits the take step
/// by step as `convert` does, within float rounding (a test holds them together).
pub fn compile_take(dir: &Path, item: &Item, options: &Options) -> Result<Clip, Error> {
    compile_take_timed(dir, item, options).map(|(clip, _)| clip)
}

/// [`compile_take`], and how long each of its stages took.
pub fn compile_take_timed(
    dir: &Path,
    item: &Item,
    options: &Options,
) -> Result<(Clip, Stages), Error> {
    let mut stages = Stages::default();
    let start = std::time::Instant::now();
    let take = prepare(item, options, true)?;
    stages.load = start.elapsed();
    let posed = quaternions::posed(&take, &item.path, options, &mut stages)?;
    let start = std::time::Instant::now();
    let clip = with_humanml3d(item, options, finish(dir, item, options, take, posed))?;
    stages.derived = start.elapsed();
    Ok((clip, stages))
}

/// [`compile_take`] the plain way, step by step with the edits `convert` makes: the take scaled
/// to metres, turned to Y up, its bone axes baked and resampled (each a pass over its channels,
/// with Euler angles between), then forward kinematics and each rotation from the channels.
pub fn compile_take_plain(dir: &Path, item: &Item, options: &Options) -> Result<Clip, Error> {
    let take = prepare(item, options, false)?;
    let posed = posed_plain(&take, &item.path, options)?;
    with_humanml3d(item, options, finish(dir, item, options, take, posed))
}

/// Loads `item` and checks that it can be compiled; retargets it when `options.onto` says so.
/// `pick_first`: for HumanML3D's vectors, at a rate the source's is a whole multiple of, the
/// frames kept are picked before retargeting rather than after (the same frames, bit for bit
/// as the resampling keeps them; only the retargeted take's height differs, by where its
/// lowest point is over fewer frames, which HumanML3D's floor takes away).
fn prepare(item: &Item, options: &Options, pick_first: bool) -> Result<Prepared, Error> {
    let path = &item.path;
    let mut loaded = load_checked(item, options)?;
    let source = (loaded.motion.frame_time, loaded.motion.frame_count());
    if pick_first && options.features == FeatureSet::HumanMl3d && !options.lock_feet {
        pick_frames(&mut loaded, options)?;
    }
    let (loaded, uncarried, check) = match &options.onto {
        Some(target) => {
            let (loaded, uncarried, check) = put_onto(target, loaded, path, options)?;
            (loaded, uncarried, Some(check))
        }
        None => (loaded, Vec::new(), None),
    };
    let mode =
        match pose::written_for_other_mode(&loaded.skeleton, &loaded.motion, OffsetMode::Replace) {
            Some(_) => OffsetMode::Add,
            None => OffsetMode::Replace,
        };
    let mut stance = loaded.stance(mode);
    if let Some(target) = &options.onto {
        // A retargeted take stands as its target does (one frame says little about it).
        stance.up = target.up;
        stance.up_given = target.up_given;
    }
    let mut loaded = loaded;
    if options.lock_feet && options.onto.is_none() {
        // Planted feet held where they landed (`convert --lock-feet`), before any posing.
        let (motion, _) = crate::edit::lock_feet(
            &loaded.skeleton,
            &loaded.motion,
            mode,
            stance.up,
            f64::from(stance.units.metres),
            &crate::edit::LockFeet::default(),
        )?;
        loaded.motion = motion;
    }
    Ok(Prepared {
        loaded,
        mode,
        stance,
        uncarried,
        check,
        source,
    })
}

/// `item` loaded, refused if it is motion without its skeleton, has a name the manifest cannot
/// hold, or has no rate or no frames.
fn load_checked(item: &Item, options: &Options) -> Result<crate::take::Take, Error> {
    let path = &item.path;
    if item.is_unpaired_motion() {
        return Err(Error::usage(format!(
            "{}: motion without a skeleton ({} is not beside it)",
            path.display(),
            item.wanted_skeleton()
        )));
    }
    for name in std::iter::once(path).chain(&item.motion) {
        if name.to_str().is_none() {
            return Err(Error::usage(format!(
                "{}: the name is not UTF-8, which the manifest (JSON) cannot hold",
                name.display()
            )));
        }
    }
    let mut loaded = crate::take::load_take(
        path,
        &crate::take::OpenOptions {
            motion: item.motion.clone(),
            max_size: Some(options.max_size),
            threads: Some(1),
            units: options.units,
            up: options.up,
            ..Default::default()
        },
    )?;
    // A map's `[stated.<fingerprint>]` says what this rig's takes are, where the options do not.
    let stated = options.map.stated_for(&loaded.skeleton);
    loaded.given(
        stated.units.filter(|_| options.units.is_none()),
        stated.up.filter(|_| options.up.is_none()),
    )?;
    let frame_time = loaded.motion.frame_time;
    if !(frame_time > 0.0 && frame_time.is_finite()) {
        return Err(Error::usage(format!(
            "{}: Frame Time {frame_time}: no rate to resample from, nor to take velocities at",
            path.display()
        )));
    }
    if loaded.motion.frame_count() == 0 {
        return Err(Error::usage(format!(
            "{}: no frames to learn from (a skeleton without motion)",
            path.display()
        )));
    }
    Ok(loaded)
}

/// Keeps only the frames the resampling to `options.fps` would keep, where it keeps whole
/// frames (the source's rate a whole multiple of the dataset's).
fn pick_frames(loaded: &mut crate::take::Take, options: &Options) -> Result<(), Error> {
    let motion = &loaded.motion;
    let picks = crate::edit::resample_picks(
        motion.frame_count(),
        motion.frame_time,
        options.fps,
        motion.channels,
    )?;
    if let crate::edit::Picks::Rows(rows) = picks
        && rows.len() < motion.frame_count()
    {
        let mut data = Vec::with_capacity(rows.len() * motion.channels);
        for &row in &rows {
            data.extend_from_slice(motion.frame(row));
        }
        loaded.motion = crate::Motion::new(1.0 / options.fps, motion.channels, rows.len(), data);
    }
    Ok(())
}

/// `loaded` retargeted onto `target` (`--onto`), with what it could not carry and its check.
fn put_onto(
    target: &crate::retarget::Target,
    loaded: crate::take::Take,
    path: &Path,
    options: &Options,
) -> Result<(crate::take::Take, Vec<String>, crate::retarget::Check), Error> {
    let pairs = options.map.for_skeleton(&loaded.skeleton);
    let name = path.display().to_string();
    let insist = crate::retarget::Insist {
        any_body: options.any_body,
        force: options.force,
    };
    // The clip checks itself as `retarget` does: a side crossed or a width collapsed
    // skips the take with the reason, unless `force`.
    let put = target.apply_up(
        &name,
        &loaded.skeleton,
        &loaded.motion,
        loaded.stated_up,
        &pairs,
        insist,
        1,
    )?;
    let mut uncarried = put.uncarried;
    if let Some(why) = put.forced {
        uncarried.push(format!("retarget: kept as `force` asks though {why}"));
    }
    // On the target, as the user said the target is (its units, its axis), or guessed.
    let mut on_target = crate::take::Take::new(put.skeleton, put.motion, name.clone());
    target.state_on(&mut on_target);
    // Planted feet held where they landed, during the source's contacts; the check measured
    // again on what is written.
    let (locked, check) = match options.lock_feet {
        true => {
            let motion = crate::retarget::lock_feet_from_source(&loaded, &on_target)?.0;
            let check = target.measure(
                &name,
                &loaded.skeleton,
                &loaded.motion,
                loaded.stated_up,
                &pairs,
                &motion,
            )?;
            if let Some(why) = check
                .refusal()
                .filter(|_| !options.any_body && !options.force)
            {
                return Err(Error::usage(format!(
                    "{name} onto {}: skipped: once its feet are locked, {why}",
                    target.name
                )));
            }
            (Some(motion), check)
        }
        false => (None, put.check),
    };
    let take = crate::take::Take {
        skeleton: on_target.skeleton,
        motion: locked.unwrap_or(on_target.motion),
        stated_units: on_target.stated_units,
        units_given: on_target.units_given,
        stated_up: on_target.stated_up,
        ..loaded
    };
    Ok((take, uncarried, check))
}

/// The plain posing of [`compile_take_plain`].
fn posed_plain(take: &Prepared, path: &Path, options: &Options) -> Result<Posed, Error> {
    let (skeleton, motion) = (&take.loaded.skeleton, &take.loaded.motion);
    let mode = take.mode;
    let (skeleton, motion) = crate::edit::scale(skeleton, motion, take.stance.units.metres)?;
    let (skeleton, motion) = crate::edit::reorient(&skeleton, &motion, take.stance.up, Up::Y)?;
    // An ASF bone turns about an axis of its own, which BVH cannot say: baked into plain
    // channels, so that the group's skeleton is a BVH and Euler angles mean its channels.
    let (skeleton, motion) = match skeleton.joints.iter().any(|j| j.axis.is_some()) {
        true => crate::edit::bake_axes(&skeleton, &motion)?,
        false => (skeleton, motion),
    };
    // At the file's own rate every frame is kept, at a whole fraction of it every k-th, bit for
    // bit (`edit::resample`, as `convert` and Python resample).
    let motion = crate::edit::resample(&skeleton, &motion, options.fps)?;
    let frames = motion.frame_count();
    let points = skeleton.joints.len();

    let plan = FkPlan::new(&skeleton, mode);
    let mut scratch = FkScratch::default();
    let mut batch_out = Vec::new();
    let mut world: Vec<Vec3> = Vec::with_capacity(frames * points);
    let rows: Vec<&[f32]> = (0..frames).map(|f| motion.frame(f)).collect();
    for batch in rows.chunks(pose::LANES) {
        plan.positions_of_frames(batch, &mut batch_out, &mut scratch);
        world.extend_from_slice(&batch_out);
    }

    let (topology, names) = topology_of(path, &skeleton, options, mode)?;
    let width = options.rotations.width();
    let mut rotations = vec![0.0f32; frames * topology.rotated.len() * width];
    let mut translations = Vec::with_capacity(frames * topology.translated.len() * 3);
    for (f, out) in rotations
        .chunks_mut(topology.rotated.len() * width)
        .enumerate()
    {
        for (&joint, slot) in topology.rotated.iter().zip(out.chunks_mut(width)) {
            let joint = &skeleton.joints[joint as usize];
            pose::write_rotation(joint, joint.values(rows[f]), options.rotations, slot);
        }
        for &joint in &topology.translated {
            let joint = &skeleton.joints[joint as usize];
            let t = pose::joint_translation(joint, joint.values(rows[f]), mode);
            translations.extend_from_slice(&t.to_array());
        }
    }
    drop(rows);
    Ok(Posed {
        skeleton,
        topology,
        names,
        frames,
        world,
        rotations,
        translations,
    })
}

/// The clip of a posed take: root translations, velocities and foot contacts from the world
/// positions, and what the manifest says about the take.
fn finish(dir: &Path, item: &Item, options: &Options, take: Prepared, posed: Posed) -> Clip {
    let Posed {
        skeleton,
        topology,
        names,
        frames,
        mut world,
        mut rotations,
        mut translations,
    } = posed;
    let (stance, mode) = (&take.stance, take.mode);
    let points = skeleton.joints.len();
    if options.ground {
        ground(
            &skeleton,
            &topology,
            options.feet.is_some(),
            &mut world,
            &mut translations,
        );
    }
    if options.quat_continuous && options.rotations == RotationKind::Quat {
        continuous_quaternions(&mut rotations, topology.rotated.len());
    }
    let travel = crate::model::body::travel_joint(&skeleton, &world);
    // HumanML3D's vectors have velocities and contacts of their own (`with_humanml3d`).
    let (derived, contacts) = match options.features {
        FeatureSet::Arrays => (
            Derived::of(&world, points, travel, options),
            contacts(&world, points, &topology.feet, options),
        ),
        FeatureSet::HumanMl3d => (
            Derived {
                velocities: Vec::new(),
                root_translations: Vec::new(),
            },
            Vec::new(),
        ),
    };
    // Every clip is at the dataset's one rate.
    let metrics = clip_metrics(&skeleton, &names, &world, 1.0 / options.fps);
    let mut positions = world;
    if options.root_relative {
        for pose in positions.chunks_mut(points) {
            let centre = pose[travel];
            for point in pose.iter_mut() {
                point.x -= centre.x;
                point.z -= centre.z;
            }
        }
    }
    let about = About {
        source: Source::of(dir, item),
        source_frame_time: take.source.0,
        source_frames: take.source.1,
        up: match stance.up {
            Up::Y => "y",
            Up::Z => "z",
        }
        .to_string(),
        units: stance.units.name.to_string(),
        metres_per_unit: stance.units.metres,
        units_given: stance.units_basis == crate::model::stance::UnitsBasis::Given,
        up_given: stance.up_given,
        offset_mode: match mode {
            OffsetMode::Replace => "replace",
            OffsetMode::Add => "add",
        }
        .to_string(),
        travel_joint: names[travel].clone(),
        // The stance guessed once (its up axis is not in any warning).
        warnings: {
            // The manifest is read by whoever uses the dataset: its words name arguments as
            // the library does (`offset_mode add`).
            let mut warnings: Vec<String> = crate::info::warnings_with(&take.loaded, mode, stance)
                .iter()
                .map(ToString::to_string)
                .collect();
            warnings.extend(take.uncarried.iter().cloned());
            if options.feet.is_none() && feet_of(&skeleton, mode).1 {
                let feet: Vec<&str> = topology
                    .feet
                    .iter()
                    .map(|&p| names[p as usize].as_str())
                    .collect();
                warnings.push(format!(
                    "feet: no ankle read below each leg; contacts are for points guessed from \
                     the rest pose ({}); name them with `feet`",
                    if feet.is_empty() {
                        "none found".to_string()
                    } else {
                        feet.join(", ")
                    }
                ));
            }
            warnings
        },
        retarget_check: take.check.clone(),
        metrics,
    };
    let clip = Clip {
        about,
        topology,
        frames,
        positions: flat(positions),
        rotations,
        translations,
        root_translations: derived.root_translations,
        velocities: flat(derived.velocities),
        contacts,
        rest_offsets: skeleton
            .joints
            .iter()
            .flat_map(|j| j.offset.to_array())
            .collect(),
        skeleton: Some(skeleton),
        humanml3d: None,
    };
    match options.out_units {
        Some(units) if units.metres != 1.0 => in_out_units(clip, units),
        _ => clip,
    }
}

/// The clip's lengths from metres into `units` (`--out-units`): every position, translation,
/// velocity and OFFSET, and its skeleton's; contacts and metrics were measured in metres before.
fn in_out_units(mut clip: Clip, units: crate::model::stance::Units) -> Clip {
    let per_metre = (1.0 / f64::from(units.metres)) as f32;
    for lengths in [
        &mut clip.positions,
        &mut clip.translations,
        &mut clip.root_translations,
        &mut clip.velocities,
        &mut clip.rest_offsets,
    ] {
        lengths.iter_mut().for_each(|v| *v *= per_metre);
    }
    if let Some(skeleton) = &mut clip.skeleton {
        for joint in &mut skeleton.joints {
            joint.offset *= per_metre;
        }
    }
    clip
}

/// The clip's plausibility as written (`world`: its points, metres, y up, `frame_time` apart),
/// as `bvhview metrics` measures it; `None` for a body without two feet.
fn clip_metrics(
    skeleton: &crate::Skeleton,
    names: &[String],
    world: &[Vec3],
    frame_time: f64,
) -> Option<crate::dataset::clip::ClipMetrics> {
    let body = crate::model::body::Body::of(skeleton);
    let feet = body.foot_points(skeleton);
    if feet.len() < 4 || frame_time.is_nan() || frame_time <= 0.0 {
        return None;
    }
    let figure = crate::metrics::Figure {
        names: names.to_vec(),
        points: world.iter().map(|p| p.as_dvec3()).collect(),
        feet: vec![feet[1], feet[3]],
        soles: body.sole_points(skeleton),
        bones: skeleton
            .joints
            .iter()
            .enumerate()
            .filter_map(|(j, joint)| Some((joint.parent?, j)))
            .collect(),
        hips: body.hips,
        fps: 1.0 / frame_time,
    };
    let measured = crate::metrics::measure(&figure, &crate::metrics::Thresholds::default()).ok()?;
    Some(crate::dataset::clip::ClipMetrics::of(&measured))
}

/// With `--features humanml3d`, the clip's 22 SMPL joints in HumanML3D's representation
/// ([`crate::humanml3d::features`]); the take is skipped, with why, where it has none (a take
/// of one frame).
fn with_humanml3d(item: &Item, options: &Options, mut clip: Clip) -> Result<Clip, Error> {
    if options.features != FeatureSet::HumanMl3d {
        return Ok(clip);
    }
    let names = &clip.topology.joints;
    let order = crate::solve::SMPL22_ORDER
        .iter()
        .map(|name| names.iter().position(|n| n == name))
        .collect::<Option<Vec<usize>>>()
        .ok_or_else(|| {
            Error::usage(
                Message::from(format!("{}: ", item.path.display()))
                    .argument("features", Some("humanml3d"))
                    .text(": the skeleton the take is on lacks SMPL's joint names"),
            )
        })?;
    let points = names.len();
    let positions: Vec<glam::DVec3> = clip
        .positions
        .chunks_exact(points * 3)
        .flat_map(|pose| {
            order.iter().map(move |&k| {
                glam::DVec3::new(
                    pose[3 * k].into(),
                    pose[3 * k + 1].into(),
                    pose[3 * k + 2].into(),
                )
            })
        })
        .collect();
    let features = crate::humanml3d::features(&positions)
        .map_err(|e| e.about(&item.path.display().to_string()))?;
    clip.humanml3d = Some(features);
    Ok(clip)
}

/// Points as one flat list of coordinates: the same memory, seen as floats (a `Vec3` is three
/// `f32`s with nothing between them).
fn flat(points: Vec<Vec3>) -> Vec<f32> {
    bytemuck::allocation::cast_vec(points)
}

/// What one pass over the world positions gives: each point's velocity in every frame (metres
/// per second: the central difference, one-sided at the first and last frame, 0 in a take of
/// one frame) and the travel joint's path.
struct Derived {
    velocities: Vec<Vec3>,
    root_translations: Vec<f32>,
}

impl Derived {
    fn of(world: &[Vec3], points: usize, travel: usize, options: &Options) -> Derived {
        let frames = world.len() / points.max(1);
        let fps = options.fps as f32;
        let mut derived = Derived {
            velocities: Vec::with_capacity(world.len()),
            root_translations: Vec::with_capacity(frames * 3),
        };
        for f in 0..frames {
            let (before, after) = (f.saturating_sub(1), (f + 1).min(frames - 1));
            let span = (after - before) as f32;
            let pose = &world[f * points..(f + 1) * points];
            let (from, to) = (
                &world[before * points..(before + 1) * points],
                &world[after * points..(after + 1) * points],
            );
            if span == 0.0 {
                derived
                    .velocities
                    .extend(std::iter::repeat_n(Vec3::ZERO, points));
            } else {
                let rate = fps / span;
                derived
                    .velocities
                    .extend(from.iter().zip(to).map(|(&a, &b)| (b - a) * rate));
            }
            derived
                .root_translations
                .extend_from_slice(&pose[travel].to_array());
        }
        derived
    }
}

/// Compiles `items` (found under `dir`, whose relative paths the manifest gives) on `threads`
/// threads into the dataset folder `out`, which must not exist or be empty. `done(source, error,
/// finished, total)` is called for every take in order, with the error the take was skipped for;
/// it returns false to stop (an interrupt), and then nothing is written. `takes` says which run
/// of which list `items` are ([`whole_list`], [`piece`]): a compile of a whole list of which no
/// take compiled is refused and writes nothing too (a piece of a bigger compile may have none).
pub fn compile(
    dir: &Path,
    items: Vec<Item>,
    options: &Options,
    threads: usize,
    out: &Path,
    takes: store::Takes,
    mut done: impl FnMut(&Source, Option<&Error>, usize, usize) -> bool + Send,
) -> Result<Summary, Error> {
    let require_clips = takes.first == 0 && takes.count == takes.listed;
    let mut writer = store::Writer::create(out, options, takes)?;
    let total = items.len();
    let mut failure = None;
    let mut clips = 0;
    crate::io::parallel::map_in_order(
        total,
        threads,
        4 * threads.max(1),
        |index| {
            let item = &items[index];
            compile_take(dir, item, options)
                .and_then(|clip| refuse_non_finite(item, clip))
                .map_err(|e| (Source::of(dir, item), e))
        },
        |index, result| {
            let outcome = match result {
                Ok(clip) => {
                    clips += 1;
                    match done(&clip.about.source, None, index + 1, total) {
                        true => writer.add(&clip),
                        false => Err(Error::usage("interrupted".to_string())),
                    }
                }
                Err((source, error)) => {
                    let go_on = done(&source, Some(&error), index + 1, total);
                    // The manifest's words name arguments as the library does.
                    writer.skip(Skipped {
                        error: relative_error(dir, &error.to_string()),
                        source,
                    });
                    match go_on {
                        true => Ok(()),
                        false => Err(Error::usage("interrupted".to_string())),
                    }
                }
            };
            match outcome {
                Ok(()) => true,
                Err(e) => {
                    failure = Some(e);
                    false
                }
            }
        },
    );
    if let Some(e) = failure {
        return Err(e);
    }
    if require_clips && clips == 0 {
        // Every reason: the caller may not have shown them (Python's compile raises this).
        let reasons: String = writer
            .skipped()
            .iter()
            .map(|s| format!("\n  {}", s.error))
            .collect();
        return Err(Error::usage(format!(
            "{}: no take could be compiled ({} skipped), so no dataset was written:{reasons}",
            dir.display(),
            crate::io::error::counted(total, "take")
        )));
    }
    writer.finish()
}

/// A clip whose arrays hold a number that is not finite (a take's numbers too large for
/// float32: `OFFSET 0 3e38 3e38` makes infinite positions) is refused, naming the take, the
/// array, the frame and the point: no writer writes such numbers.
fn refuse_non_finite(item: &Item, clip: Clip) -> Result<Clip, Error> {
    let points = clip.topology.joints.len().max(1);
    let rotated = clip.topology.rotated.len().max(1);
    let width = clip.rotations.len() / (clip.frames.max(1) * rotated).max(1);
    let point = |k: usize| clip.topology.joints.get(k).map_or("?", |n| n.as_str());
    let translated = clip.topology.translated.len();
    let arrays: [(&str, &[f32], usize, Option<usize>); 6] = [
        ("positions", &clip.positions, points * 3, Some(3)),
        (
            "rotations",
            &clip.rotations,
            rotated * width.max(1),
            Some(width.max(1)),
        ),
        ("translations", &clip.translations, translated * 3, Some(3)),
        ("root_translations", &clip.root_translations, 3, None),
        ("velocities", &clip.velocities, points * 3, Some(3)),
        ("rest_offsets", &clip.rest_offsets, points * 3, Some(3)),
    ];
    for (name, values, per_frame, per_point) in arrays {
        let Some(at) = crate::edit::first_non_finite(values) else {
            continue;
        };
        let take = match &item.motion {
            Some(amc) => format!("{} + {}", item.path.display(), amc.display()),
            None => item.path.display().to_string(),
        };
        let whose = match (name, per_point) {
            ("rest_offsets", _) => format!("the OFFSET of {}", point(at / 3)),
            ("rotations" | "translations", Some(w)) => {
                let list = match name {
                    "rotations" => &clip.topology.rotated,
                    _ => &clip.topology.translated,
                };
                let joint = list.get(at % per_frame / w);
                format!(
                    "frame {}, joint {}",
                    at / per_frame,
                    joint.map_or("?", |&j| point(j as usize))
                )
            }
            (_, Some(w)) => format!(
                "frame {}, point {}",
                at / per_frame,
                point(at % per_frame / w)
            ),
            (_, None) => format!("frame {}", at / per_frame),
        };
        return Err(Error::usage(format!(
            "{take}: {name} overflow: {} at {whose}; the take's numbers are too large for \
             float32 (its OFFSETs or channel values), so it is not written",
            values[at]
        )));
    }
    Ok(clip)
}

/// An error as the manifest keeps it: paths relative to the folder compiled, so that the
/// manifest is the same however the folder was named (`tests/data`, `/work/tests/data/`).
fn relative_error(dir: &Path, error: &str) -> String {
    let prefix = dir.display().to_string();
    if prefix.is_empty() {
        return error.to_string();
    }
    let prefix = format!("{}/", prefix.trim_end_matches('/'));
    error.replace(&prefix, "")
}

/// What a compile of all of `items` (found under `dir`) holds: the whole list.
pub fn whole_list(dir: &Path, items: &[Item]) -> store::Takes {
    let sources: Vec<Source> = items.iter().map(|item| Source::of(dir, item)).collect();
    store::Takes {
        list: store::list_digest(&sources),
        listed: items.len(),
        first: 0,
        count: items.len(),
    }
}

/// Piece `index` of `pieces` of the list `items`: consecutive runs in list order, the first
/// `len % pieces` of them one take longer. [`merge::merge`] joins the pieces back.
pub fn piece(
    dir: &Path,
    items: Vec<Item>,
    index: usize,
    pieces: usize,
) -> Result<(Vec<Item>, store::Takes), Error> {
    if pieces == 0 || index >= pieces {
        return Err(Error::usage(format!(
            "piece {index} of {pieces}: expected 0 <= piece < pieces"
        )));
    }
    let whole = whole_list(dir, &items);
    let (size, extra) = (items.len() / pieces, items.len() % pieces);
    let first = index * size + index.min(extra);
    let count = size + usize::from(index < extra);
    let run = items.into_iter().skip(first).take(count).collect();
    Ok((
        run,
        store::Takes {
            first,
            count,
            ..whole
        },
    ))
}

/// The items given by paths relative to `dir` (or absolute): `(path, motion)` pairs.
pub fn items_in(dir: &Path, pairs: &[(PathBuf, Option<PathBuf>)]) -> Vec<Item> {
    pairs
        .iter()
        .map(|(path, motion)| Item {
            path: dir.join(path),
            motion: motion.as_ref().map(|m| dir.join(m)),
        })
        .collect()
}
