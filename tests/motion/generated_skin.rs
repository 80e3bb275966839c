//! The generated skin: in the rest pose it is the mesh it was made as, and the middle of each
//! bone moves rigidly with its joint.

use crate::common;
use bvhview::model::bone_skin::{Body, PosedBody};
use bvhview::model::pose::{OffsetMode, world_matrices};
use common::*;

#[test]
fn rest_pose_reproduces_the_bind_mesh_and_bone_middles_move_rigidly() {
    let bvh = load("bvh/bvh11_131_01.bvh");
    let body = Body::new(&bvh.skeleton, OffsetMode::Replace);
    let (mut posed, mut scratch) = (PosedBody::default(), (Vec::new(), Vec::new()));
    body.pose(&bvh.skeleton, None, &mut posed, &mut scratch);
    assert_eq!(posed.positions.len(), body.skin.vertices.len());
    assert!(posed.indices.len() > 1000 && posed.indices.len() % 3 == 0);
    for (p, v) in posed.positions.iter().zip(&body.skin.vertices) {
        assert!(p.abs_diff_eq(v.position, 1e-4), "{p} vs {}", v.position);
    }
    // Frame 400: a vertex with a single influence is its joint's world × inverse rest world.
    let frame = bvh.motion.frame(400);
    body.pose(&bvh.skeleton, Some(frame), &mut posed, &mut scratch);
    let (mut now, mut rest) = (Vec::new(), Vec::new());
    world_matrices(&bvh.skeleton, frame, OffsetMode::Replace, &mut now);
    world_matrices(&bvh.skeleton, &[], OffsetMode::Replace, &mut rest);
    let mut checked = 0;
    for (i, v) in body.skin.vertices.iter().enumerate() {
        if v.influences[0].1 == 1.0 {
            let bone = v.influences[0].0 as usize;
            let want = (now[bone] * rest[bone].inverse()).transform_point3(v.position);
            assert!(posed.positions[i].abs_diff_eq(want, 1e-3), "vertex {i}");
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked}");
}

/// `draw_triangles` is safe to call with any arrays: an index past them draws nothing instead of
/// letting GL read outside them; in-range indices draw.
#[test]
fn draw_triangles_with_an_index_past_the_arrays_draws_nothing() {
    use bvhview::render::fixed::{FixedFunction, GL_COLOR_BUFFER_BIT, GL_DEPTH_BUFFER_BIT};
    let positions = [
        glam::Vec3::new(-0.5, -0.5, 0.0),
        glam::Vec3::new(0.5, -0.5, 0.0),
        glam::Vec3::new(0.0, 0.5, 0.0),
    ];
    let normals = [glam::Vec3::Z; 3];
    let mut pictures = Vec::new();
    for indices in [&[0u32, 1, 3][..], &[0, 1, u32::MAX], &[0, 1, 2]] {
        let mut renderer = bvhview::render::Renderer::new(32, 32).unwrap();
        let context = renderer.context();
        context.gl.clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        context.gl.draw_triangles(&positions, &normals, indices);
        let lit = context.read_rgb().iter().filter(|&&b| b > 0).count();
        pictures.push(lit);
    }
    assert_eq!(pictures[..2], [0, 0], "nothing drawn");
    assert!(
        pictures[2] > 100,
        "the in-range triangle is drawn: {pictures:?}"
    );
}
