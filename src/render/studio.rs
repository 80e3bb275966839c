//! The studio look (`--look studio`, V in the window): a dark backdrop, a grid floor at the
//! take's lowest point, the figure's shadow cast straight down onto it, bones and joints coloured
//! by side (left blue, right orange, centre grey), sticks with the spheres, and a camera that
//! frames the pose shown, or follows the root (T), above the HUD (`paint`). Its sizes come from the skeleton: the grid's squares are half a metre in
//! the units the skeleton's height suggests. None of it is the article's picture, which stays the
//! default.

use crate::model::body::{Side, name_side};
use crate::model::motion::Motion;
use crate::model::pose::{FkPlan, FkScratch, OffsetMode, Up};
use crate::model::skeleton::Skeleton;
use crate::model::stance::Units;
use crate::render::draw::{self, Style};
use crate::render::fixed::{
    FixedFunction, GL_AMBIENT, GL_COLOR_BUFFER_BIT, GL_COLOR_MATERIAL, GL_DEPTH_BUFFER_BIT,
    GL_DIFFUSE, GL_LIGHTING, GL_LINES, GL_NORMALIZE,
};
use crate::render::scene::{Scene, look_at};
use glam::Vec3;

/// How far above the level the studio camera looks down, in radians.
pub const PITCH: f32 = 0.3;

/// Everything the look needs to know about one take, worked out once.
#[derive(Clone, Debug, PartialEq)]
pub struct Stage {
    pub units: Units,
    /// The rest pose's standing height, in the file's units.
    pub height: f32,
    /// The lowest point of the whole take, standing: where the floor goes.
    pub floor: f32,
    /// The grid's spacing (half a metre) and extent: x from, x to, z from, z to, each a multiple
    /// of the spacing.
    pub spacing: f32,
    pub grid: [f32; 4],
    /// A sphere around every joint of every frame: what the camera frames.
    pub center: Vec3,
    pub radius: f32,
}

/// The direction the shadow's light shines in: down, and across to +x and −z.
const LIGHT: Vec3 = Vec3::new(0.45, -1.0, -0.3);

const LEFT: [f32; 3] = [0.35, 0.6, 1.0];
const RIGHT: [f32; 3] = [1.0, 0.55, 0.25];
const CENTRE: [f32; 3] = [0.82, 0.82, 0.8];

/// The lowest and highest corner of a box around every joint of every frame of a take, stood up
/// (the rest pose for a take without frames).
pub fn take_extent(skeleton: &Skeleton, motion: &Motion, mode: OffsetMode, up: Up) -> (Vec3, Vec3) {
    take_extent_of(skeleton, motion, mode, up, None)
}

/// [`take_extent`] of the joints `only` marks (all with `None`): a character's box is its
/// mesh's joints', not its rig's controls left standing where they were.
pub fn take_extent_of(
    skeleton: &Skeleton,
    motion: &Motion,
    mode: OffsetMode,
    up: Up,
    only: Option<&[bool]>,
) -> (Vec3, Vec3) {
    let counts = |j: usize| only.is_none_or(|only| only.get(j).copied().unwrap_or(false));
    let stand = up.to_y_up();
    let plan = FkPlan::new(skeleton, mode);
    let (mut points, mut scratch) = (Vec::new(), FkScratch::default());
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    let mut take = |frame: &[f32]| {
        plan.positions(frame, &mut points, &mut scratch);
        for (j, p) in points.iter().enumerate() {
            if !counts(j) {
                continue;
            }
            let p = stand * *p;
            lo = lo.min(p);
            hi = hi.max(p);
        }
    };
    if motion.frame_count() == 0 {
        // The rest pose: no row for the plan to read.
        let rest = crate::model::pose::world_positions(skeleton, &[], mode);
        for (j, p) in rest.into_iter().enumerate() {
            if !counts(j) {
                continue;
            }
            let p = stand * p;
            lo = lo.min(p);
            hi = hi.max(p);
        }
    } else {
        for frame in 0..motion.frame_count() {
            take(motion.frame(frame));
        }
    }
    if lo.x > hi.x {
        (Vec3::ZERO, Vec3::ZERO)
    } else {
        (lo, hi)
    }
}

/// The studio grid's squares widen beyond this many along either axis.
const MOST_GRID_LINES: f32 = 200.0;

impl Stage {
    /// The stage under one take, its height and units guessed from its motion.
    pub fn new(skeleton: &Skeleton, motion: &Motion, mode: OffsetMode, up: Up) -> Stage {
        let extent = take_extent(skeleton, motion, mode, up);
        let stance = crate::model::stance::Stance::guess(skeleton, motion, mode, None);
        Stage::around(
            &[(extent, Vec3::ZERO)],
            stance.height_along(up),
            Some(stance.units),
        )
    }

    /// The stage under several takes, each with its extent and where it stands; `height` is the
    /// tallest one's (it sets the sizes) and `units` the first one's (the grid's squares are
    /// half a metre in them; guessed from `height` when not given).
    pub fn around(takes: &[((Vec3, Vec3), Vec3)], height: f32, units: Option<Units>) -> Stage {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for &((take_lo, take_hi), origin) in takes {
            lo = lo.min(take_lo + origin);
            hi = hi.max(take_hi + origin);
        }
        if lo.x > hi.x {
            (lo, hi) = (Vec3::ZERO, Vec3::ZERO);
        }
        // A skeleton with no height along the up axis (one joint, or lying flat) is sized by its
        // extent instead, and a single point by one unit, so that its spheres still show.
        let height = if height > 1e-6 {
            height
        } else {
            let across = (hi - lo).length();
            if across > 1e-6 { across } else { 1.0 }
        };
        let units = units.unwrap_or_else(|| Units::guess(height));
        let center = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(height * 0.5).max(1e-3);
        // A metre of floor beyond the takes on every side, on whole squares of half a metre;
        // squares ten times as wide for each tenfold beyond MOST_GRID_LINES along either axis
        // (a take that travels kilometres gets a coarser grid, not millions of lines).
        let margin = 1.0 / units.metres;
        let mut spacing = 0.5 / units.metres;
        let travel = (hi.x - lo.x).max(hi.z - lo.z) + 2.0 * margin;
        while travel / spacing > MOST_GRID_LINES && spacing.is_finite() {
            spacing *= 10.0;
        }
        let snap_down = |v: f32| (v / spacing).floor() * spacing;
        let snap_up = |v: f32| (v / spacing).ceil() * spacing;
        let grid = [
            snap_down(lo.x - margin),
            snap_up(hi.x + margin),
            snap_down(lo.z - margin),
            snap_up(hi.z + margin),
        ];
        Stage {
            units,
            height,
            floor: lo.y,
            spacing,
            grid,
            center,
            radius,
        }
    }

    /// The spheres' radius: in proportion to the figure.
    pub fn sphere_radius(&self) -> f64 {
        f64::from(self.height.max(1e-3)) * 0.012
    }
}

/// Each joint's colour: its own name's side, else its parent's (so a hand's fingers follow it),
/// else the centre's.
pub fn side_colours(skeleton: &Skeleton) -> Vec<[f32; 3]> {
    let mut sides: Vec<Option<Side>> = Vec::with_capacity(skeleton.joints.len());
    for joint in &skeleton.joints {
        // Joints come in pre-order: a parent's side is known before its children's.
        let own = name_side(&joint.name).map(|(side, _)| side);
        sides.push(own.or_else(|| joint.parent.and_then(|p| sides[p])));
    }
    sides
        .into_iter()
        .map(|side| match side {
            Some(Side::Left) => LEFT,
            Some(Side::Right) => RIGHT,
            None => CENTRE,
        })
        .collect()
}

/// The look's `display()` for one or more takes side by side (each scene one take; the first
/// one's camera for all): backdrop, grid, then each take's shadow and figure, lit in its colours.
/// Leaves the state the article's `init` set (black clear colour, lighting on, its green, GL's
/// default material).
pub fn display<G: FixedFunction>(gl: &mut G, scenes: &[Scene], stage: &Stage, picture_height: u32) {
    let Some(first) = scenes.first() else {
        return;
    };
    gl.clear_color(0.12, 0.13, 0.16, 0.0);
    gl.clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl.clear_color(0.0, 0.0, 0.0, 0.0);
    gl.load_identity();
    look_at(gl, first.camera.eye(), first.camera.target, [0.0, 1.0, 0.0]);

    gl.disable(GL_LIGHTING);
    gl.line_width(1.0);
    gl.color3f(0.3, 0.32, 0.38);
    gl.begin(GL_LINES);
    let [x0, x1, z0, z1] = stage.grid;
    let y = stage.floor;
    let lines = |from: f32, to: f32| {
        let count = ((to - from) / stage.spacing).round().max(0.0) as usize;
        (0..=count).map(move |i| from + i as f32 * stage.spacing)
    };
    for x in lines(x0, x1) {
        gl.vertex3f(x, y, z0);
        gl.vertex3f(x, y, z1);
    }
    for z in lines(z0, z1) {
        gl.vertex3f(x0, y, z);
        gl.vertex3f(x1, y, z);
    }
    gl.end();
    // Sticks and shadows as thick on the picture as the figure is tall on it: 3 pixels at the
    // article's 600, at least 1.
    let line_width = (picture_height as f32 / 200.0).clamp(1.0, 8.0);
    for scene in scenes {
        shadow(gl, scene, stage, line_width);
    }
    gl.line_width(line_width);

    gl.enable(GL_LIGHTING);
    gl.enable(GL_COLOR_MATERIAL);
    for scene in scenes {
        figure(gl, scene);
    }
    gl.disable(GL_COLOR_MATERIAL);
    gl.line_width(3.0);
    // Colour material left the last colour in the material: back to GL's defaults, which the
    // article's grey spheres are lit with.
    gl.materialfv(GL_AMBIENT, [0.2, 0.2, 0.2, 1.0]);
    gl.materialfv(GL_DIFFUSE, [0.8, 0.8, 0.8, 1.0]);
    gl.color3f(0.0, 1.0, 0.0);
}

/// Every bone cast onto the floor, just above the grid, by a light high up to one side (a point
/// p lands at p − d·(p.y − floor)/d.y, d the light's direction). Unlit, line width 4.
fn shadow<G: FixedFunction>(gl: &mut G, scene: &Scene, stage: &Stage, line_width: f32) {
    let points: Vec<Vec3> = crate::model::pose::world_positions(
        scene.skeleton,
        scene.frame.unwrap_or(&[]),
        scene.offset_mode,
    )
    .into_iter()
    .map(|p| scene.place(p))
    .collect();
    let shadow_y = stage.floor + stage.height * 0.002;
    let cast = |p: Vec3| {
        let along = (p.y - stage.floor) / LIGHT.y;
        [p.x - LIGHT.x * along, shadow_y, p.z - LIGHT.z * along]
    };
    gl.color3f(0.05, 0.05, 0.07);
    // A skin casts its triangles (a character's rig may hold controls apart from its body):
    // `cast ∘ place` is affine, so GL projects the skin's own vertices through one matrix (no
    // copy of a mesh a frame).
    if let Some(skin) = scene.skin {
        let origin = Vec3::from_array(cast(scene.place(Vec3::ZERO)));
        let column = |axis: Vec3| Vec3::from_array(cast(scene.place(axis))) - origin;
        let (x, y, z) = (column(Vec3::X), column(Vec3::Y), column(Vec3::Z));
        #[rustfmt::skip]
        let onto_floor = [
            x.x, x.y, x.z, 0.0,
            y.x, y.y, y.z, 0.0,
            z.x, z.y, z.z, 0.0,
            origin.x, origin.y, origin.z, 1.0,
        ];
        gl.push_matrix();
        gl.mult_matrixf(&onto_floor);
        // A closed surface casts its outline twice, once by the faces towards the light and
        // once by those away; seen from above the floor, the faces towards the light keep
        // their winding, so a skin that hides its back faces casts them alone.
        let from_above = scene.camera.eye()[1] > stage.floor;
        crate::render::scene::draw_skin(gl, skin, skin.single_sided && from_above);
        gl.pop_matrix();
        return;
    }
    gl.line_width(line_width * 4.0 / 3.0);
    gl.begin(GL_LINES);
    // Stepping through the recursion (J) shows the first `shown` joints: so does the shadow.
    let shown = scene.shown.unwrap_or(usize::MAX);
    for (index, joint) in scene.skeleton.joints.iter().enumerate() {
        for &child in joint.children.iter().filter(|&&c| c < shown) {
            for [x, y, z] in [cast(points[index]), cast(points[child])] {
                gl.vertex3f(x, y, z);
            }
        }
    }
    gl.end();
}

/// The take's skin and skeleton at its place, in its colours (colour material on).
fn figure<G: FixedFunction>(gl: &mut G, scene: &Scene) {
    gl.push_matrix();
    gl.translatef(scene.origin[0], scene.origin[1], scene.origin[2]);
    crate::render::scene::scale_take(gl, scene.scale);
    if scene.up == Up::Z {
        gl.rotatef(-90.0, 1.0, 0.0, 0.0);
    }
    if let Some(skin) = scene.skin {
        gl.color3f(0.78, 0.74, 0.7);
        crate::render::scene::draw_skin(gl, skin, skin.single_sided);
    }
    let style = match (scene.skin, scene.style) {
        (None, style) => Some(style),
        (Some(_), Style::Points) => None,
        (Some(_), _) => Some(Style::Sticks),
    };
    if let Some(style) = style {
        let pass = draw::Pass {
            shown: scene.shown,
            sphere_radius: scene.sphere_radius,
            colours: scene.colours,
            ..draw::Pass::whole(scene.skeleton, scene.frame, style, scene.offset_mode)
        };
        draw::draw_pass(gl, &pass);
    }
    gl.pop_matrix();
    gl.disable(GL_NORMALIZE);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_are_guessed_from_the_height() {
        assert_eq!(Units::guess(170.0).name, "centimetres");
        assert_eq!(Units::guess(1.75).name, "metres");
        assert_eq!(Units::guess(16.4).name, "decimetres");
        assert_eq!(Units::guess(1700.0).name, "millimetres");
        assert_eq!(Units::guess(68.0).name, "inches");
        // CMU's takes stand about 25 units tall: 2.5 m in decimetres is nearer to a person than
        // 0.66 m in inches.
        assert_eq!(Units::guess(26.0).name, "decimetres");
    }

    #[test]
    fn a_rest_pose_has_a_stage_too() {
        let text = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n\
                    End Site\n{\nOFFSET 0 170 0\n}\n}\nMOTION\nFrames: 0\nFrame Time: 0.1\n";
        let bvh = crate::bvh::load_bytes(text.as_bytes(), "t.bvh").unwrap();
        let extent = take_extent(&bvh.skeleton, &bvh.motion, OffsetMode::Replace, Up::Y);
        assert_eq!(extent, (Vec3::ZERO, Vec3::new(0.0, 170.0, 0.0)));
    }

    #[test]
    fn sides_come_from_names_and_pass_to_children() {
        let text = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n\
                    JOINT LeftArm\n{\nOFFSET 1 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n\
                    JOINT Finger1\n{\nOFFSET 1 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n\
                    End Site\n{\nOFFSET 1 0 0\n}\n}\n}\n\
                    JOINT rhumerus\n{\nOFFSET -1 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n\
                    End Site\n{\nOFFSET -1 0 0\n}\n}\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n\
                    0 0 0 0 0 0 0 0 0 0 0 0\n";
        let bvh = crate::bvh::load_bytes(text.as_bytes(), "t.bvh").unwrap();
        assert_eq!(
            side_colours(&bvh.skeleton),
            vec![CENTRE, LEFT, LEFT, LEFT, RIGHT, RIGHT]
        );
    }

    #[test]
    fn a_skeleton_without_height_is_sized_by_its_extent() {
        // One joint whose End Site lies along x: no height along y.
        let flat = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n\
                    End Site\n{\nOFFSET 40 0 0\n}\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n";
        let bvh = crate::bvh::load_bytes(flat.as_bytes(), "t.bvh").unwrap();
        let stage = Stage::new(&bvh.skeleton, &bvh.motion, OffsetMode::Replace, Up::Y);
        assert_eq!(stage.height, 40.0);
        assert_eq!(stage.sphere_radius(), 40.0 * 0.012);
        // A single point: one unit.
        let point = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n\
                     }\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n";
        let bvh = crate::bvh::load_bytes(point.as_bytes(), "t.bvh").unwrap();
        let stage = Stage::new(&bvh.skeleton, &bvh.motion, OffsetMode::Replace, Up::Y);
        assert_eq!((stage.height, stage.radius), (1.0, 0.5));
    }

    #[test]
    fn the_stage_holds_the_whole_take() {
        // A figure 180 units tall (so centimetres) walking from x = 0 to x = 300, its feet
        // dipping to y = -5 in the second frame.
        let text = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\n\
                    CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n\
                    JOINT Head\n{\nOFFSET 0 80 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n\
                    End Site\n{\nOFFSET 0 10 0\n}\n}\n\
                    JOINT Foot\n{\nOFFSET 0 -80 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n\
                    End Site\n{\nOFFSET 0 -10 0\n}\n}\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n\
                    0 90 0 0 0 0 0 0 0 0 0 0\n300 85 0 0 0 0 0 0 0 0 0 0\n";
        let bvh = crate::bvh::load_bytes(text.as_bytes(), "t.bvh").unwrap();
        let stage = Stage::new(&bvh.skeleton, &bvh.motion, OffsetMode::Replace, Up::Y);
        assert_eq!(stage.height, 180.0);
        assert_eq!(stage.units.name, "centimetres");
        assert_eq!(stage.floor, -5.0);
        assert_eq!(stage.spacing, 50.0);
        // x from 0 to 300 and z 0, with a metre (100) beyond, on 50-unit squares.
        assert_eq!(stage.grid, [-100.0, 400.0, -100.0, 100.0]);
        assert_eq!(stage.center, Vec3::new(150.0, 87.5, 0.0));
        // Beside a second take 400 along x, the stage covers both.
        let extent = take_extent(&bvh.skeleton, &bvh.motion, OffsetMode::Replace, Up::Y);
        let both = Stage::around(
            &[(extent, Vec3::ZERO), (extent, Vec3::new(400.0, 0.0, 0.0))],
            180.0,
            None,
        );
        assert_eq!(both.grid, [-100.0, 800.0, -100.0, 100.0]);
        // A take that travels 2 km (200 000 cm): squares of 50 m, 42 lines along x instead of
        // over 4000.
        let far = Stage::around(
            &[(
                (Vec3::new(0.0, 0.0, 0.0), Vec3::new(200_000.0, 180.0, 0.0)),
                Vec3::ZERO,
            )],
            180.0,
            None,
        );
        assert_eq!(far.spacing, 5000.0);
        assert_eq!(far.grid, [-5000.0, 205_000.0, -5000.0, 5000.0]);
    }
}
