//! A camera that frames points into part of the picture: the free room below the HUD and the
//! labels and above the timeline, as the GL projection will draw them (the article's 45°
//! perspective, `gluLookAt` towards the target). Used by `--fit` and the studio look; the
//! article's own camera never is.

use crate::render::scene::Camera;
use glam::{Mat4, Vec3, Vec4Swizzles};

/// The part of a picture a framed figure may use, in pixels from the bottom-left corner.
///
/// ```
/// use bvhview::render::framing::Room;
///
/// // A 600 × 400 picture with a 40-pixel HUD on top and a 20-pixel timeline below.
/// let room = Room::below(600, 400, 40.0, 20.0);
/// assert_eq!(room, Room { left: 0.0, right: 600.0, bottom: 20.0, top: 360.0 });
/// // Too small to keep both: a third of the height stays free.
/// let tiny = Room::below(60, 30, 20.0, 20.0);
/// assert_eq!(tiny.top - tiny.bottom, 10.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Room {
    /// The left edge, in pixels from the left.
    pub left: f32,
    /// The right edge, in pixels from the left.
    pub right: f32,
    /// The bottom edge, in pixels from the bottom.
    pub bottom: f32,
    /// The top edge, in pixels from the bottom.
    pub top: f32,
}

impl Room {
    /// The whole of a `width × height` picture, less `top` pixels along the top (the HUD, the
    /// labels) and `bottom` along the bottom (the timeline). A picture too small to keep both
    /// keeps at least a third of its height.
    pub fn below(width: u32, height: u32, top: f32, bottom: f32) -> Room {
        let h = height as f32;
        let (mut top, mut bottom) = (top.max(0.0), bottom.max(0.0));
        let least = h / 3.0;
        if h - top - bottom < least {
            let over = (least - (h - top - bottom)) / (top + bottom).max(1.0);
            top -= top * over;
            bottom -= bottom * over;
        }
        Room {
            left: 0.0,
            right: width as f32,
            bottom,
            top: h - top,
        }
    }
}

/// The projection and view GL draws with for `camera` on a `width × height` picture: the
/// article's 45° perspective (its planes as `scene::reshape` sets them) and a look at the target.
pub fn view_projection(camera: &Camera, width: u32, height: u32) -> Mat4 {
    let aspect = width as f32 / height.max(1) as f32;
    let distance = camera.distance;
    let (near, far) = (1.0f32.min(distance / 20.0), 1000.0f32.max(distance * 5.0));
    // gluPerspective's matrix and gluLookAt's, as `scene::reshape` and `scene::display` issue
    // them (glam is built without its projection helpers).
    let cotangent = 1.0 / 22.5f32.to_radians().tan();
    let projection = Mat4::from_cols_array(&[
        cotangent / aspect,
        0.0,
        0.0,
        0.0,
        0.0,
        cotangent,
        0.0,
        0.0,
        0.0,
        0.0,
        -(far + near) / (far - near),
        -1.0,
        0.0,
        0.0,
        -2.0 * near * far / (far - near),
        0.0,
    ]);
    let eye = Vec3::from_array(camera.eye());
    let forward = (Vec3::from_array(camera.target) - eye).normalize_or_zero();
    let side = forward.cross(Vec3::Y).normalize_or_zero();
    let up = side.cross(forward);
    let view = Mat4::from_cols(
        side.extend(0.0),
        up.extend(0.0),
        (-forward).extend(0.0),
        glam::Vec4::W,
    )
    .transpose()
        * Mat4::from_translation(-eye);
    projection * view
}

/// Where `point` lands in pixels from the bottom-left corner, or `None` behind the eye.
pub fn project(matrix: &Mat4, point: Vec3, width: u32, height: u32) -> Option<(f32, f32)> {
    let clip = *matrix * point.extend(1.0);
    if clip.w <= 1e-6 {
        return None;
    }
    let ndc = clip.xy() / clip.w;
    Some((
        (ndc.x + 1.0) * 0.5 * width as f32,
        (ndc.y + 1.0) * 0.5 * height as f32,
    ))
}

/// The pixel box of `points` under `camera`, or `None` when a point is behind the eye.
fn pixel_box(camera: &Camera, points: &[Vec3], (width, height): (u32, u32)) -> Option<Room> {
    let matrix = view_projection(camera, width, height);
    let mut room = Room {
        left: f32::MAX,
        right: f32::MIN,
        bottom: f32::MAX,
        top: f32::MIN,
    };
    for &p in points {
        let (x, y) = project(&matrix, p, width, height)?;
        room.left = room.left.min(x);
        room.right = room.right.max(x);
        room.bottom = room.bottom.min(y);
        room.top = room.top.max(y);
    }
    Some(room)
}

/// How much of the room the framed points fill along its tighter side.
const FILL: f32 = 0.9;

/// A camera at `angle` and `pitch` that shows every point inside `room`, as large as fits (the
/// box of the points fills 90 % (`FILL`) of the room along its tighter side, centred in it). Found by
/// projecting the points and correcting the distance and the target a few times: a perspective
/// view has no closed form for the box of a set of points.
pub fn fit(points: &[Vec3], angle: f32, pitch: f32, size: (u32, u32), room: Room) -> Camera {
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for p in points.iter().filter(|p| p.is_finite()) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    if lo.x > hi.x {
        (lo, hi) = (Vec3::ZERO, Vec3::ZERO);
    }
    let center = (lo + hi) * 0.5;
    // Points all in one place have no size to frame: a unit around them, as the article's
    // sphere of radius 1 would need.
    let across = (hi - lo).length();
    let radius = if across > 1e-6 {
        (across * 0.5).max(center.length() * 1e-4)
    } else {
        1.0
    };
    let points: Vec<Vec3> = points.iter().copied().filter(|p| p.is_finite()).collect();
    let half_fov = 22.5f32.to_radians();
    // Far enough that the bounding sphere is in view whatever the angle: every point in front.
    let mut camera = Camera {
        angle,
        target: center.to_array(),
        distance: radius / half_fov.sin() * 1.1,
        pitch,
    };
    if points.is_empty() || across <= 1e-6 {
        return camera;
    }
    let (width, height) = (size.0.max(1), size.1.max(1));
    let room_w = (room.right - room.left).max(1.0);
    let room_h = (room.top - room.bottom).max(1.0);
    let inside = |seen: &Room| {
        seen.left >= room.left
            && seen.right <= room.right
            && seen.bottom >= room.bottom
            && seen.top <= room.top
    };
    // Eight rounds of sizing and centring, then (rarely needed) rounds that centre and step back
    // until every point is in the room: the corrections converge from either side.
    for round in 0..40 {
        let Some(seen) = pixel_box(&camera, &points, (width, height)) else {
            camera.distance *= 1.5;
            continue;
        };
        let seen_w = (seen.right - seen.left).max(1e-3);
        let seen_h = (seen.top - seen.bottom).max(1e-3);
        let zoom = if round < 8 {
            (seen_w / (room_w * FILL)).max(seen_h / (room_h * FILL))
        } else if inside(&seen) {
            break;
        } else {
            1.05
        };
        // Move the target so that the box's centre goes to the room's: a pixel at the target's
        // depth is 2·d·tan(fov/2)/height world units.
        let per_pixel = 2.0 * camera.distance * half_fov.tan() / height as f32;
        let dx = ((room.left + room.right) - (seen.left + seen.right)) * 0.5 * per_pixel;
        let dy = ((room.bottom + room.top) - (seen.bottom + seen.top)) * 0.5 * per_pixel;
        let eye = Vec3::from_array(camera.eye());
        let target = Vec3::from_array(camera.target);
        let forward = (target - eye).normalize_or_zero();
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let up = right.cross(forward);
        // Moving the target right moves the picture left.
        let moved = target - right * dx - up * dy;
        camera.target = moved.to_array();
        camera.distance *= zoom.clamp(0.25, 4.0);
    }
    camera
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_are_framed_inside_the_room() {
        // A figure 170 tall and 40 wide, far from the origin.
        let points: Vec<Vec3> = (0..=10)
            .flat_map(|i| {
                let y = i as f32 * 17.0;
                [Vec3::new(480.0, y, -20.0), Vec3::new(520.0, y, 20.0)]
            })
            .collect();
        let size = (600, 600);
        let room = Room::below(600, 600, 150.0, 30.0);
        assert_eq!((room.bottom, room.top), (30.0, 450.0));
        for angle in [0.0f32, 1.0, 10.0] {
            for pitch in [0.0f32, 0.3] {
                let camera = fit(&points, angle, pitch, size, room);
                let seen = pixel_box(&camera, &points, size).expect("in front");
                assert!(seen.left >= 0.0 && seen.right <= 600.0, "{seen:?}");
                assert!(seen.bottom >= 30.0 && seen.top <= 450.0, "{seen:?}");
                // Tall figure: its height fills most of the room's 420 pixels.
                let tall = seen.top - seen.bottom;
                assert!(tall > 0.8 * 420.0, "{angle} {pitch}: {tall}");
            }
        }
    }

    #[test]
    fn points_in_one_place_keep_a_unit_around_them() {
        let points = [Vec3::new(100.0, 50.0, 0.0); 3];
        let camera = fit(
            &points,
            10.0,
            0.0,
            (600, 600),
            Room::below(600, 600, 0.0, 0.0),
        );
        assert!(camera.distance > 2.0, "{camera:?}");
        assert_eq!(camera.target, [100.0, 50.0, 0.0]);
    }

    #[test]
    fn a_room_low_in_the_picture_still_holds_every_point() {
        let points: Vec<Vec3> = (0..=10)
            .map(|i| Vec3::new(0.0, i as f32 * 17.0, 0.0))
            .collect();
        // 160×120 with the top 80 pixels taken: a room 40 high, below the middle.
        let room = Room::below(160, 120, 80.0, 0.0);
        let camera = fit(&points, 0.5, 0.3, (160, 120), room);
        let seen = pixel_box(&camera, &points, (160, 120)).unwrap();
        assert!(
            seen.bottom >= room.bottom && seen.top <= room.top,
            "{seen:?} {room:?}"
        );
    }

    #[test]
    fn a_small_picture_keeps_a_third_for_the_figure() {
        let room = Room::below(160, 120, 100.0, 30.0);
        assert!((room.top - room.bottom - 40.0).abs() < 1e-3, "{room:?}");
    }
}
