//! One picture of one or more takes, worked out the same way for the window and for `snapshot`:
//! which frame of each take the timeline is at, where each take stands, the camera, the skins,
//! then the article's `reshape` and `display` and the overlay. The window and `snapshot` both
//! call [`Painter::paint`], so the window shows what `snapshot` writes.

use crate::io::error::Error;
use crate::model::bone_skin::{Body, PosedBody};
use crate::model::motion::Motion;
use crate::model::pose::{OffsetMode, Up, world_matrices, world_positions};
use crate::model::skeleton::Skeleton;
use crate::model::stance::Stance;
use crate::render::current_frame::frame_values;
use crate::render::fixed::FixedFunction;
use crate::render::framing::{self, Room};
use crate::render::options::{Look, SnapshotOptions};
use crate::render::overlay::{Overlay, draw_overlay};
use crate::render::scene::{self, Camera, Scene};
use crate::render::studio::{self, Stage, take_extent_of};
use glam::Vec3;

/// One take to show.
#[derive(Clone, Copy, Debug)]
pub struct Shown<'a> {
    pub skeleton: &'a Skeleton,
    pub motion: &'a Motion,
    /// Its up axis (a Z-up take is stood up).
    pub up: Up,
    /// How it stands, as guessed from its motion: its height and units size the studio and
    /// scale several takes to one height.
    pub stance: Stance,
    /// A character's mesh bound to `skeleton`, drawn skinned in the skeleton's place
    /// (`--character`); `None`: the skeleton as asked.
    pub mesh: Option<&'a crate::model::mesh::Mesh>,
}

impl<'a> Shown<'a> {
    /// The offset mode its bones are drawn in: `asked` (`--offset-mode`, O in the window), or
    /// a character's ([`OffsetMode::for_take`]).
    pub fn offset_mode(&self, asked: OffsetMode) -> OffsetMode {
        asked.for_take(self.mesh.is_some())
    }

    /// A take as the file is written (or stood up by `up`), its stance guessed from its motion
    /// when `framed` (a framed or studio view sizes itself by it), else from its rest pose
    /// alone: the article's view uses none of it, and a picture per frame should not pay for it.
    pub fn of(
        skeleton: &'a Skeleton,
        motion: &'a Motion,
        up: Up,
        mode: OffsetMode,
        framed: bool,
    ) -> Self {
        let stance = if framed {
            Stance::guess(skeleton, motion, mode, None)
        } else {
            Stance::at_rest(skeleton, mode)
        };
        Shown {
            skeleton,
            motion,
            up,
            stance,
            mesh: None,
        }
    }
}

/// One timeline for several takes, each at its own Frame Time. It ticks at the finest Frame Time
/// among them and runs to the last frame of the longest; each take shows the frame its own clock
/// has reached at a tick. With one take a tick is simply its frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clock {
    /// Seconds per tick.
    pub step: f64,
    /// Ticks, 1 at least.
    pub count: usize,
    single: bool,
}

/// How far apart (relatively) two frame times may be and still count as one: frame times are
/// often written to five or six digits (0.033333 beside 0.0333333).
const SLACK: f64 = 1e-4;

/// A frame time playback can count with: the file's, or 1/30 s when it is not above 0.
fn usable(frame_time: f64) -> f64 {
    if frame_time > 0.0 && frame_time.is_finite() {
        frame_time
    } else {
        1.0 / 30.0
    }
}

/// Ticks of `step` seconds per frame of `frame_time` (1 or more, `step` being the finest): a whole
/// number when it is one to within [`SLACK`], so that takes at the same rate written two ways keep
/// the same frame at every tick, however long they run.
fn ticks_per_frame(frame_time: f64, step: f64) -> f64 {
    let ratio = usable(frame_time) / step;
    let whole = ratio.round();
    if (ratio - whole).abs() <= ratio * SLACK {
        whole
    } else {
        ratio
    }
}

impl Clock {
    pub fn new(motions: &[&Motion]) -> Clock {
        if let [motion] = motions {
            return Clock {
                step: usable(motion.frame_time),
                count: motion.frame_count().max(1),
                single: true,
            };
        }
        let step = motions
            .iter()
            .map(|m| usable(m.frame_time))
            .fold(f64::INFINITY, f64::min);
        let step = if step.is_finite() { step } else { 1.0 / 30.0 };
        // Ticks to reach the last frame of every take: the first tick at or past its end.
        let last_tick = motions
            .iter()
            .map(|m| {
                let last = (m.frame_count().max(1) - 1) as f64;
                (last * ticks_per_frame(m.frame_time, step) - 1e-9).ceil()
            })
            .fold(0.0, f64::max);
        let count = last_tick.clamp(0.0, u32::MAX as f64) as usize + 1;
        Clock {
            step,
            count,
            single: false,
        }
    }

    /// Seconds at a tick.
    pub fn seconds(&self, tick: usize) -> f64 {
        tick as f64 * self.step
    }

    /// The frame `motion` shows at `tick`: the last one its clock has reached, held at its end.
    pub fn frame_of(&self, motion: &Motion, tick: usize) -> usize {
        let last = motion.frame_count().max(1) - 1;
        if self.single {
            return tick;
        }
        let reached = (tick as f64 / ticks_per_frame(motion.frame_time, self.step) + 1e-9).floor();
        (reached.min(last as f64)) as usize
    }
}

/// Where each take stands: one take at the origin (the article's picture); several side by side
/// along x in the order given, each moved so that its box over the whole take starts a quarter
/// of the tallest one's height after the previous one's ends, the row centred on x = 0, and
/// each one's lowest point at the first one's (they stand on one floor).
pub fn side_by_side(extents: &[(Vec3, Vec3)], tallest: f32) -> Vec<Vec3> {
    if extents.len() <= 1 {
        return vec![Vec3::ZERO; extents.len()];
    }
    let gap = tallest * 0.25;
    let floor = extents[0].0.y;
    let mut origins = Vec::with_capacity(extents.len());
    let mut cursor = 0.0f32;
    for (lo, hi) in extents {
        origins.push(Vec3::new(cursor - lo.x, floor - lo.y, 0.0));
        cursor += hi.x - lo.x + gap;
    }
    let width = cursor - gap;
    for origin in &mut origins {
        origin.x -= width * 0.5;
    }
    origins
}

/// Where each take stands when they are drawn one over the other: where its file puts it (a
/// retargeted take walks the source's path), its lowest point over the take at the first one's.
pub fn one_over_other(extents: &[(Vec3, Vec3)]) -> Vec<Vec3> {
    let Some(&(floor, _)) = extents.first() else {
        return Vec::new();
    };
    extents
        .iter()
        .map(|&(lo, _)| Vec3::new(0.0, floor.y - lo.y, 0.0))
        .collect()
}

/// A colour halfway to white: the takes drawn over the first one.
fn paler(colour: [f32; 3]) -> [f32; 3] {
    colour.map(|c| c + (1.0 - c) * 0.55)
}

/// The camera's start angle: the article's for one take; for several, 90° (the eye on +z), which
/// sees takes standing side by side along x across the picture.
pub fn start_angle(takes: usize) -> f32 {
    if takes > 1 {
        std::f32::consts::FRAC_PI_2
    } else {
        scene::START_ANGLE
    }
}

/// What the painter works out once for a set of takes: their boxes, places and the stage.
#[derive(Clone, Debug)]
struct Layout {
    /// What it was worked out for: each take's skeleton and motion addresses and sizes, the
    /// offset mode and up axes (the caller calls [`Painter::forget`] when takes are replaced).
    key: Vec<(usize, usize, usize, usize, Up)>,
    mode: OffsetMode,
    true_scale: bool,
    overlaid: bool,
    /// Each take's box over all its frames (scaled and stood up, before it is moved to its
    /// place), when a view needs it.
    extents: Vec<(Vec3, Vec3)>,
    /// Each take's scale (the first's is 1) and height standing, in the first take's units.
    scales: Vec<f32>,
    heights: Vec<f32>,
    origins: Vec<Vec3>,
    stage: Option<Stage>,
    colours: Vec<Vec<[f32; 3]>>,
}

/// Draws pictures of takes, keeping what is costly to work out (skins, the stage, the places)
/// from one picture to the next.
#[derive(Default)]
pub struct Painter {
    layout: Option<Layout>,
    /// Each take's skin, made the first time it is shown.
    bodies: Vec<Option<Body>>,
    posed: Vec<PosedBody>,
    scratch: (Vec<glam::Mat4>, Vec<glam::Mat4>),
}

impl Painter {
    /// Forgets everything worked out: the takes or how they are drawn have changed.
    pub fn forget(&mut self) {
        self.layout = None;
        self.bodies.clear();
    }

    fn layout(&mut self, takes: &[Shown], options: &SnapshotOptions, studio_look: bool) -> &Layout {
        let mode = options.offset_mode;
        let key: Vec<_> = takes
            .iter()
            .map(|t| {
                (
                    t.skeleton as *const Skeleton as usize,
                    t.motion as *const Motion as usize,
                    t.skeleton.joints.len(),
                    t.motion.frame_count(),
                    t.up,
                )
            })
            .collect();
        let boxes_needed = takes.len() > 1 || studio_look || options.whole_take;
        let fresh = self.layout.as_ref().is_some_and(|l| {
            l.key == key
                && l.mode == mode
                && l.true_scale == options.true_scale
                && l.overlaid == options.overlaid
                && l.stage.is_some() == studio_look
                && (!boxes_needed || l.extents.len() == takes.len())
        });
        if !fresh {
            self.bodies.clear();
            // A take whose stance was guessed in the other offset mode (it looks written for
            // that one) is drawn collapsed in this one: its standing height says nothing of what
            // is drawn, so its pose alone is framed and its box sizes the stage.
            let own_heights: Vec<f32> = takes
                .iter()
                .map(|t| {
                    if t.stance.mode == t.offset_mode(mode) {
                        t.stance.height_along(t.up)
                    } else {
                        0.0
                    }
                })
                .collect();
            let scales = take_scales(takes, &own_heights, options.true_scale);
            let heights: Vec<f32> = own_heights
                .iter()
                .zip(&scales)
                .map(|(h, s)| h * s)
                .collect();
            // One take stands where it is: its box is only needed for the stage or `--fit=take`.
            let extents: Vec<(Vec3, Vec3)> = if boxes_needed {
                takes
                    .iter()
                    .zip(&scales)
                    .map(|(t, &scale)| {
                        let bound = t.mesh.map(|m| m.bound_joints(t.skeleton.joints.len()));
                        let (lo, hi) = take_extent_of(
                            t.skeleton,
                            t.motion,
                            t.offset_mode(mode),
                            t.up,
                            bound.as_deref(),
                        );
                        (lo * scale, hi * scale)
                    })
                    .collect()
            } else {
                Vec::new()
            };
            let tallest = heights.iter().copied().fold(0.0, f32::max);
            let origins = if takes.len() > 1 && options.overlaid {
                one_over_other(&extents)
            } else if takes.len() > 1 {
                side_by_side(&extents, tallest)
            } else {
                vec![Vec3::ZERO; takes.len()]
            };
            let stage = studio_look.then(|| {
                let placed: Vec<_> = extents.iter().copied().zip(origins.clone()).collect();
                let units = takes.first().map(|t| t.stance.units);
                Stage::around(&placed, tallest, units)
            });
            let colours = takes
                .iter()
                .enumerate()
                .map(|(index, t)| {
                    let colours = studio::side_colours(t.skeleton);
                    if options.overlaid && index > 0 {
                        colours.into_iter().map(paler).collect()
                    } else {
                        colours
                    }
                })
                .collect();
            self.layout = Some(Layout {
                key,
                mode,
                true_scale: options.true_scale,
                overlaid: options.overlaid,
                extents,
                scales,
                heights,
                origins,
                stage,
                colours,
            });
        }
        self.layout.as_ref().expect("made above")
    }

    /// Poses each take's skin for its frame: a character's own mesh, or with `--skin` the
    /// generated one.
    fn pose_skins(
        &mut self,
        takes: &[Shown],
        frames: &[Option<&[f32]>],
        options: &SnapshotOptions,
    ) {
        let mode = options.offset_mode;
        if !takes.iter().any(|take| options.skin || take.mesh.is_some()) {
            return;
        }
        self.bodies.resize_with(takes.len(), || None);
        self.posed.resize_with(takes.len(), PosedBody::default);
        for (index, take) in takes.iter().enumerate() {
            if let Some(mesh) = take.mesh {
                // A character's own mesh, bound in its rest pose (channels 0).
                let frame = frames[index].unwrap_or(&[]);
                world_matrices(
                    take.skeleton,
                    frame,
                    OffsetMode::Replace,
                    &mut self.scratch.0,
                );
                mesh.pose(&self.scratch.0, &mut self.posed[index]);
            } else if options.skin {
                let body = self.bodies[index].get_or_insert_with(|| Body::new(take.skeleton, mode));
                body.pose(
                    take.skeleton,
                    frames[index],
                    &mut self.posed[index],
                    &mut self.scratch,
                );
            }
        }
    }

    /// The camera [`Painter::paint`] draws `takes` with, for the same arguments.
    pub fn camera(
        &mut self,
        takes: &[Shown],
        options: &SnapshotOptions,
        overlay: &Overlay,
        moved: Option<&Camera>,
    ) -> Result<Camera, Error> {
        let frames = frames_at(takes, options)?;
        let layout = self
            .layout(takes, options, options.look == Look::Studio)
            .clone();
        self.pose_skins(takes, &frames, options);
        Ok(camera_of(
            &layout,
            takes,
            &frames,
            &self.posed,
            options,
            overlay,
            moved,
        ))
    }

    /// Draws `takes` at tick `options.frame` of their [`Clock`] into the current context of
    /// `gl`, `options.width × options.height` pixels, with `overlay` on top. `moved`: the
    /// window's camera (the article's as the user turned, tilted, panned and zoomed it); in a
    /// framed or studio view the same moves apply to the camera `snapshot` starts from, so with
    /// none the window draws what `snapshot` writes.
    pub fn paint<G: FixedFunction>(
        &mut self,
        gl: &mut G,
        takes: &[Shown],
        options: &SnapshotOptions,
        overlay: &Overlay,
        moved: Option<&Camera>,
    ) -> Result<(), Error> {
        let frames = frames_at(takes, options)?;
        let mode = options.offset_mode;
        let studio_look = options.look == Look::Studio;
        let layout = self.layout(takes, options, studio_look).clone();
        if takes.is_empty() {
            return Ok(());
        }
        let framed = options.fit || studio_look;
        self.pose_skins(takes, &frames, options);
        let skinned = |take: &Shown| options.skin || take.mesh.is_some();
        let camera = camera_of(
            &layout,
            takes,
            &frames,
            &self.posed,
            options,
            overlay,
            moved,
        );
        // Sizes follow the figure: the studio's from its height, a framed view's from the
        // camera's distance, the article's its own 1.
        let sphere_radius = match &layout.stage {
            Some(stage) => stage.sphere_radius(),
            None => scene::sphere_radius(&camera, framed),
        };
        let scenes: Vec<Scene> = takes
            .iter()
            .enumerate()
            .map(|(index, take)| Scene {
                skeleton: take.skeleton,
                frame: frames[index],
                camera,
                style: options.style,
                offset_mode: take.offset_mode(mode),
                skin: skinned(take).then(|| &self.posed[index]),
                // The step view follows the first take's recursion.
                shown: if index == 0 { options.step } else { None },
                // Drawn under the take's scale: the same size on the picture for every take.
                sphere_radius: sphere_radius / f64::from(layout.scales[index]),
                up: take.up,
                origin: layout.origins[index].to_array(),
                scale: layout.scales[index],
                colours: layout
                    .stage
                    .as_ref()
                    .map(|_| layout.colours[index].as_slice()),
            })
            .collect();
        scene::reshape(gl, options.width, options.height, &camera);
        // The article's picture, or the studio look's.
        match layout.stage.as_ref() {
            Some(stage) => studio::display(gl, &scenes, stage, options.height),
            None => scene::display_all(gl, &scenes),
        }
        draw_overlay(gl, &scenes, (options.width, options.height), overlay);
        Ok(())
    }
}

/// Each take's MOTION row at tick `options.frame` of their [`Clock`].
fn frames_at<'a>(
    takes: &[Shown<'a>],
    options: &SnapshotOptions,
) -> Result<Vec<Option<&'a [f32]>>, Error> {
    let clock = Clock::new(&takes.iter().map(|t| t.motion).collect::<Vec<_>>());
    if takes.len() > 1 && options.frame >= clock.count {
        return Err(Error::invalid(
            "frame",
            options.frame.to_string(),
            format!(
                "the takes together have frames 0 to {} (at {} s each)",
                clock.count - 1,
                clock.step
            ),
        ));
    }
    let mut frames = Vec::with_capacity(takes.len());
    for take in takes {
        frames.push(frame_values(
            take.motion,
            clock.frame_of(take.motion, options.frame),
        )?);
    }
    Ok(frames)
}

/// The camera for a picture: the article's (as the window moved it), or one that frames the
/// pose shown (or the whole take) in the room the overlay leaves, or follows the root.
fn camera_of(
    layout: &Layout,
    takes: &[Shown],
    frames: &[Option<&[f32]>],
    posed: &[PosedBody],
    options: &SnapshotOptions,
    overlay: &Overlay,
    moved: Option<&Camera>,
) -> Camera {
    let mode = options.offset_mode;
    let studio_look = options.look == Look::Studio;
    let Some(first) = takes.first() else {
        return Camera::default();
    };
    let size = (options.width, options.height);
    // Where each take's points are drawn: stood up, scaled, moved to its place.
    let placed = |index: usize, p: Vec3| {
        scene::place(
            takes[index].up,
            layout.scales[index],
            layout.origins[index],
            p,
        )
    };
    let framed = options.fit || studio_look;
    let follow_root = studio_look && options.follow;
    let room = figure_room(overlay, size, options.step.is_some());
    let pitch = if studio_look { studio::PITCH } else { 0.0 };
    let mut camera = if let (true, Some(stage)) = (follow_root, &layout.stage) {
        // Following the root: a box as wide and deep as the figure is tall around the root, from
        // the floor up, framed in the room with the pose (which may reach beyond it); the camera
        // keeps its distance as the figure moves.
        let root = first.skeleton.roots().next().map_or(Vec3::ZERO, |root| {
            let points = world_positions(
                first.skeleton,
                frames[0].unwrap_or(&[]),
                first.offset_mode(mode),
            );
            placed(0, points[root])
        });
        let half = stage.height * 0.5;
        let mut points: Vec<Vec3> = (0..8)
            .map(|corner| {
                let side = |bit: usize| if corner & bit == 0 { -half } else { half };
                let y = if corner & 2 == 0 {
                    stage.floor
                } else {
                    stage.floor + stage.height
                };
                Vec3::new(root.x + side(1), y, root.z + side(4))
            })
            .collect();
        points.extend(pose_points(takes, frames, posed, mode, layout, &placed));
        framing::fit(&points, options.angle, pitch, size, room)
    } else if framed {
        let points = if options.whole_take {
            take_corners(layout)
        } else {
            pose_points(takes, frames, posed, mode, layout, &placed)
        };
        framing::fit(&points, options.angle, pitch, size, room)
    } else {
        Camera {
            angle: options.angle,
            ..Camera::default()
        }
    };
    if let Some(moved) = moved {
        if options.fit || studio_look {
            let article = Camera::default();
            camera.angle = moved.angle;
            camera.distance *= moved.distance / article.distance;
            camera.pitch += moved.pitch;
            for axis in 0..3 {
                camera.target[axis] += moved.target[axis] - article.target[axis];
            }
            // The studio camera turns with the window's angle about its own target.
        } else {
            camera = *moved;
        }
    }
    camera
}

/// Each take's scale: 1 for the first; the others to the first one's height, or with
/// `true_scale` by their units (a take in metres beside one in centimetres is 100 times larger).
fn take_scales(takes: &[Shown], heights: &[f32], true_scale: bool) -> Vec<f32> {
    let Some(first) = takes.first() else {
        return Vec::new();
    };
    takes
        .iter()
        .zip(heights)
        .enumerate()
        .map(|(index, (take, &height))| {
            let scale = if index == 0 {
                1.0
            } else if true_scale {
                take.stance.units.metres / first.stance.units.metres
            } else {
                heights[0] / height
            };
            if scale.is_finite() && scale > 0.0 {
                scale
            } else {
                1.0
            }
        })
        .collect()
}

/// Pixels kept free along the top for each take's label.
pub const LABEL_ROOM: f32 = 14.0;

/// The part of the picture a framed figure may use: below the labels, above the HUD's lines and
/// the timeline; in the step view below the HUD's lines (the step view's text, which takes the
/// bottom, leaves it be).
pub fn figure_room(overlay: &Overlay, (width, height): (u32, u32), stepping: bool) -> Room {
    use crate::render::hud::{Place, reserved};
    let font = crate::render::text::Font::for_picture(width, height);
    let timeline = overlay.timeline.is_some() && !stepping;
    let place = Place::for_picture((width, height), timeline, stepping);
    let (mut top, hud_bottom) = reserved(overlay.lines.len(), font, place);
    if !overlay.labels.is_empty() {
        top += LABEL_ROOM;
    }
    let bar = if timeline {
        crate::render::timeline::Bar::for_picture(width, height).room()
    } else {
        0.0
    };
    let bottom = hud_bottom.max(bar);
    Room::below(width, height, top, bottom)
}

/// The corners of every take's box over all its frames, at its place: what `--fit=take` keeps
/// in view.
fn take_corners(layout: &Layout) -> Vec<Vec3> {
    layout
        .extents
        .iter()
        .zip(&layout.origins)
        .flat_map(|(&(lo, hi), &origin)| {
            (0..8).map(move |corner| {
                let pick = |bit: usize, axis: usize| {
                    if corner & bit == 0 {
                        lo[axis]
                    } else {
                        hi[axis]
                    }
                };
                Vec3::new(pick(1, 0), pick(2, 1), pick(4, 2)) + origin
            })
        })
        .collect()
}

/// The points a framed view keeps in the picture for the pose shown: every joint of every take
/// at its place, and a column as tall as the take's standing figure from its lowest point, so
/// that the camera keeps its distance while the figure crouches or lies down.
fn pose_points(
    takes: &[Shown],
    frames: &[Option<&[f32]>],
    posed: &[PosedBody],
    mode: OffsetMode,
    layout: &Layout,
    placed: &dyn Fn(usize, Vec3) -> Vec3,
) -> Vec<Vec3> {
    let mut points = Vec::new();
    for (index, take) in takes.iter().enumerate() {
        let start = points.len();
        match (take.mesh, posed.get(index)) {
            // A character is framed by its mesh as posed (its rig's controls may stand apart).
            (Some(_), Some(skin)) => {
                points.extend(skin.positions.iter().map(|&p| placed(index, p)))
            }
            _ => {
                for p in world_positions(
                    take.skeleton,
                    frames[index].unwrap_or(&[]),
                    take.offset_mode(mode),
                ) {
                    points.push(placed(index, p));
                }
            }
        }
        let pose = &points[start..];
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in pose.iter().filter(|p| p.is_finite()) {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        if lo.x <= hi.x {
            let middle = (lo + hi) * 0.5;
            let column = Vec3::new(middle.x, lo.y + layout.heights[index], middle.z);
            points.push(column);
        }
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_clock_for_takes_at_different_rates() {
        // 5 frames at 1/30 s (to 0.1333 s) and 3 frames at 1/120 s (to 0.01667 s).
        let slow = Motion::new(1.0 / 30.0, 1, 5, vec![0.0; 5]);
        let fast = Motion::new(1.0 / 120.0, 1, 3, vec![0.0; 3]);
        let clock = Clock::new(&[&slow, &fast]);
        assert_eq!(clock.step, 1.0 / 120.0);
        // The slow take's last frame is at 4/30 s = 16 ticks of 1/120 s.
        assert_eq!(clock.count, 17);
        assert_eq!(clock.frame_of(&slow, 0), 0);
        assert_eq!(clock.frame_of(&slow, 3), 0);
        assert_eq!(clock.frame_of(&slow, 4), 1);
        assert_eq!(clock.frame_of(&slow, 16), 4);
        assert_eq!(clock.frame_of(&fast, 2), 2);
        // The short take holds its last frame.
        assert_eq!(clock.frame_of(&fast, 16), 2);
        // A span that is not a whole number of ticks: 3 frames at 0.05 s end at 0.1 s, between
        // ticks 3 and 4 of 0.03 s; the clock runs to tick 4, where the last frame shows.
        let twentieth = Motion::new(0.05, 1, 3, vec![0.0; 3]);
        let thirtieth = Motion::new(0.03, 1, 2, vec![0.0; 2]);
        let clock = Clock::new(&[&twentieth, &thirtieth]);
        assert_eq!(clock.count, 5);
        assert_eq!(clock.frame_of(&twentieth, 3), 1);
        assert_eq!(clock.frame_of(&twentieth, 4), 2);
        // 30 frames per second written two ways: one clock of 69 ticks, each tick the same
        // frame of both.
        let short = Motion::new(0.033333, 1, 69, vec![0.0; 69]);
        let long = Motion::new(0.0333333, 1, 69, vec![0.0; 69]);
        let clock = Clock::new(&[&short, &long]);
        assert_eq!(clock.count, 69);
        for tick in [1, 20, 68] {
            assert_eq!(clock.frame_of(&short, tick), tick);
            assert_eq!(clock.frame_of(&long, tick), tick);
        }
        // And after an hour of them: still the same frame, the last one reached at the end.
        let hour = 108_000;
        let short = Motion::new(0.033333, 1, hour, vec![0.0; hour]);
        let long = Motion::new(0.0333333, 1, hour, vec![0.0; hour]);
        let clock = Clock::new(&[&short, &long]);
        assert_eq!(clock.count, hour);
        for tick in [10_000, 54_321, hour - 1] {
            assert_eq!(clock.frame_of(&short, tick), tick);
            assert_eq!(clock.frame_of(&long, tick), tick);
        }
        // 120 Hz beside 50 Hz (2.4 ticks a frame): an hour of each ends on the same tick.
        let fast = Motion::new(1.0 / 120.0, 1, 432_000, vec![0.0; 432_000]);
        let slow = Motion::new(0.02, 1, 180_000, vec![0.0; 180_000]);
        let clock = Clock::new(&[&fast, &slow]);
        assert_eq!(clock.count, 432_000);
        assert_eq!(clock.frame_of(&slow, 431_999), 179_999);
        assert_eq!(clock.frame_of(&slow, 431_998), 179_999);
        assert_eq!(clock.frame_of(&slow, 431_997), 179_998);
        // One take: a tick is its frame, whatever its frame time.
        let odd = Motion::new(0.0, 1, 4, vec![0.0; 4]);
        let alone = Clock::new(&[&odd]);
        assert_eq!((alone.count, alone.frame_of(&odd, 3)), (4, 3));
    }

    #[test]
    fn takes_stand_side_by_side_centred() {
        let boxes = [
            (Vec3::new(-10.0, 0.0, 0.0), Vec3::new(10.0, 1.0, 0.0)),
            (Vec3::new(100.0, 0.0, 0.0), Vec3::new(140.0, 1.0, 0.0)),
        ];
        // 20 wide, a gap of 25 (a quarter of 100), 40 wide: 85 in all, from -42.5 to 42.5.
        let origins = side_by_side(&boxes, 100.0);
        assert_eq!(origins[0], Vec3::new(-32.5, 0.0, 0.0));
        assert_eq!(origins[1], Vec3::new(-97.5, 0.0, 0.0));
        assert_eq!(boxes[0].0.x + origins[0].x, -42.5);
        assert_eq!(boxes[1].1.x + origins[1].x, 42.5);
        assert_eq!(side_by_side(&boxes[..1], 100.0), vec![Vec3::ZERO]);
    }

    #[test]
    fn takes_one_over_the_other_share_a_centre_and_a_floor() {
        let boxes = [
            (Vec3::new(-10.0, 2.0, -4.0), Vec3::new(10.0, 12.0, 6.0)),
            (Vec3::new(100.0, -5.0, 0.0), Vec3::new(140.0, 30.0, 20.0)),
        ];
        let origins = one_over_other(&boxes);
        assert_eq!(origins[0], Vec3::ZERO);
        // Where the file puts it, its floor -5 onto 2.
        assert_eq!(origins[1], Vec3::new(0.0, 7.0, 0.0));
        // Half-way and more to white: 0.2 + 0.8 × 0.55 is 0.64 to the float's last bit.
        for (got, want) in paler([0.0, 1.0, 0.2]).iter().zip([0.55, 1.0, 0.64]) {
            assert!((got - want).abs() < 1e-6, "{got} against {want}");
        }
        assert!(one_over_other(&[]).is_empty());
    }
}
