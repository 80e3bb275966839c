//! The article's picture: our offscreen snapshots against the pictures its own program drew
//! (tests/oracle/refs), the sphere against freeglut's triangles, and the GL matrix stack
//! against `pose`.

use crate::common;
use bvhview::render::fixed::{FixedFunction, GL_MODELVIEW_MATRIX, GlTable};
use bvhview::render::scene::{self, Camera, Scene};
use bvhview::render::{Image, Renderer, SnapshotOptions, draw::Style, sphere::Sphere};
use common::*;
use std::path::PathBuf;

fn oracle_input(name: &str) -> PathBuf {
    let input = oracle("inputs").join(name);
    if input.exists() {
        input
    } else {
        data(&format!("bvh/{name}"))
    }
}

/// Every picture in MANIFEST.tsv, drawn by us with the same input, frame, angle and size.
#[test]
fn snapshots_match_the_articles_pictures() {
    let manifest = std::fs::read_to_string(oracle("refs/MANIFEST.tsv")).unwrap();
    let mut checked = 0;
    for line in manifest.lines().skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        let (file, input, frame, angle, width, height) = (f[0], f[1], f[2], f[3], f[4], f[5]);
        let bvh = bvhview::bvh::load_file(&oracle_input(input), Default::default()).unwrap();
        let options = SnapshotOptions {
            frame: frame.parse().unwrap(),
            angle: angle.parse().unwrap(),
            width: width.parse().unwrap(),
            height: height.parse().unwrap(),
            ..SnapshotOptions::default()
        };
        let ours = bvhview::render::snapshot(&bvh.skeleton, &bvh.motion, &options).unwrap();
        let theirs = Image::read_png(&oracle("refs").join(file)).unwrap();
        let differing = ours.differing_pixels(&theirs);
        let allowed = (ours.width * ours.height) as usize / 1000;
        assert!(
            differing <= allowed,
            "{file}: {differing} pixels differ (at most {allowed})"
        );
        // The aim is identical pixels; every run says how close it came (scripts/test.sh
        // shows the output of passing tests).
        println!(
            "drift {file}: {differing} of {} pixels differ (at most {allowed})",
            ours.width * ours.height
        );
        checked += 1;
    }
    assert_eq!(checked, 16);
}

/// Our sphere is freeglut's: the same 16 strips of 42 (position, normal) pairs, bit for bit.
#[test]
fn sphere_matches_freeglut_triangles() {
    let text = std::fs::read_to_string(oracle("sphere_1_20_16.json")).unwrap();
    // The file's numbers after the description, in order: per strip 42 positions then 42 normals.
    let body = &text[text.find("\"strips\"").unwrap()..];
    let numbers: Vec<f32> = body
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e' || c == 'E'))
        .filter(|s| !s.is_empty() && s.chars().any(|c| c.is_ascii_digit()))
        .map(|s| s.parse::<f64>().unwrap() as f32)
        .collect();
    let sphere = Sphere::new(1.0, 20, 16);
    let strip = sphere.strip_len();
    assert_eq!(strip, 42);
    assert_eq!(numbers.len(), 16 * 42 * 6);
    for part in 0..16 {
        for k in 0..strip {
            let v = sphere.indices[part * strip + k] as usize;
            let base = part * strip * 6;
            let position = &numbers[base + k * 3..base + k * 3 + 3];
            let normal = &numbers[base + strip * 3 + k * 3..base + strip * 3 + k * 3 + 3];
            assert_eq!(
                &sphere.positions[v * 3..v * 3 + 3],
                position,
                "strip {part} vertex {k}"
            );
            assert_eq!(
                &sphere.normals[v * 3..v * 3 + 3],
                normal,
                "strip {part} normal {k}"
            );
        }
    }
}

/// Passes every call to the real GL and reads the modelview matrix where each sphere is drawn.
struct Probe<'a> {
    gl: &'a mut GlTable,
    at_spheres: Vec<[f32; 16]>,
}

impl FixedFunction for Probe<'_> {
    fn draw_triangles(&mut self, p: &[glam::Vec3], n: &[glam::Vec3], i: &[u32]) {
        self.gl.draw_triangles(p, n, i)
    }
    fn get_modelview(&mut self) -> [f32; 16] {
        self.gl.get_modelview()
    }
    fn load_matrix(&mut self, m: &[f32; 16]) {
        self.gl.load_matrix(m)
    }
    fn clear_color(&mut self, r: f32, g: f32, b: f32, a: f32) {
        self.gl.clear_color(r, g, b, a)
    }
    fn clear(&mut self, mask: u32) {
        self.gl.clear(mask)
    }
    fn enable(&mut self, cap: u32) {
        self.gl.enable(cap)
    }
    fn disable(&mut self, cap: u32) {
        self.gl.disable(cap)
    }
    fn lightfv(&mut self, l: u32, p: u32, v: [f32; 4]) {
        self.gl.lightfv(l, p, v)
    }
    fn materialfv(&mut self, p: u32, v: [f32; 4]) {
        self.gl.materialfv(p, v)
    }
    fn line_width(&mut self, w: f32) {
        self.gl.line_width(w)
    }
    fn color3f(&mut self, r: f32, g: f32, b: f32) {
        self.gl.color3f(r, g, b)
    }
    fn viewport(&mut self, x: i32, y: i32, w: i32, h: i32) {
        self.gl.viewport(x, y, w, h)
    }
    fn matrix_mode(&mut self, mode: u32) {
        self.gl.matrix_mode(mode)
    }
    fn load_identity(&mut self) {
        self.gl.load_identity()
    }
    fn mult_matrixf(&mut self, m: &[f32; 16]) {
        self.gl.mult_matrixf(m)
    }
    fn mult_matrixd(&mut self, m: &[f64; 16]) {
        self.gl.mult_matrixd(m)
    }
    fn push_matrix(&mut self) {
        self.gl.push_matrix()
    }
    fn pop_matrix(&mut self) {
        self.gl.pop_matrix()
    }
    fn translatef(&mut self, x: f32, y: f32, z: f32) {
        self.gl.translatef(x, y, z)
    }
    fn translated(&mut self, x: f64, y: f64, z: f64) {
        self.gl.translated(x, y, z)
    }
    fn rotatef(&mut self, a: f32, x: f32, y: f32, z: f32) {
        self.gl.rotatef(a, x, y, z)
    }
    fn begin(&mut self, mode: u32) {
        self.gl.begin(mode)
    }
    fn end(&mut self) {
        self.gl.end()
    }
    fn vertex3f(&mut self, x: f32, y: f32, z: f32) {
        self.gl.vertex3f(x, y, z)
    }
    fn normal3f(&mut self, x: f32, y: f32, z: f32) {
        self.gl.normal3f(x, y, z)
    }
    fn window_pos(&mut self, x: i32, y: i32) {
        self.gl.window_pos(x, y)
    }
    fn raster_pos(&mut self, x: f32, y: f32, z: f32) {
        self.gl.raster_pos(x, y, z)
    }
    fn bitmap(&mut self, width: i32, height: i32, advance: f32, bits: &[u8]) {
        self.gl.bitmap(width, height, advance, bits)
    }
    fn solid_sphere(&mut self, radius: f64, slices: i32, stacks: i32) {
        self.at_spheres
            .push(self.gl.get_matrix(GL_MODELVIEW_MATRIX));
        self.gl.solid_sphere(radius, slices, stacks)
    }
}

/// At each joint the GL modelview matrix is the view times `pose`'s world matrix.
#[test]
fn gl_matrix_stack_equals_pose_world_times_view() {
    // A chain 200 joints deep (each turned 2° about Z and 1° about X), far deeper than GL's
    // 32-matrix stack. Each level ends with an End Site drawn after the deeper joints return: it
    // is only right if every level's matrix was restored.
    let mut deep = String::from("HIERARCHY\n");
    for i in 0..200 {
        let keyword = if i == 0 { "ROOT" } else { "JOINT" };
        deep.push_str(&format!(
            "{keyword} j{i}\n{{\nOFFSET 0 0.5 0\nCHANNELS 2 Zrotation Xrotation\n"
        ));
    }
    deep.push_str(&"End Site\n{\nOFFSET 0.3 0 0\n}\n}\n".repeat(200));
    deep.push_str("MOTION\nFrames: 1\nFrame Time: 0.1\n");
    deep.push_str(&"2 1 ".repeat(200));
    deep.push('\n');
    let deep_path = crate::common::scratch_folder("deep").join("deep.bvh");
    std::fs::write(&deep_path, &deep).unwrap();
    for name in [
        "tiny_crlf.bvh",
        "bvh11_131_01.bvh",
        // Position channels on 143 joints below the root.
        "makehuman_tpose.bvh",
        "deep",
    ] {
        let path = if name == "deep" {
            deep_path.clone()
        } else {
            oracle_input(name)
        };
        let bvh = bvhview::bvh::load_file(&path, Default::default()).unwrap();
        let mut renderer = Renderer::new(64, 64).unwrap();
        let gl = &mut renderer.context().gl;
        let camera = Camera::default();
        let frame = bvh.motion.frame(bvh.motion.frame_count() - 1);
        scene::reshape(gl, 64, 64, &camera);
        gl.load_identity();
        scene::look_at(gl, camera.eye(), camera.target, [0.0, 1.0, 0.0]);
        let view = glam::Mat4::from_cols_array(&gl.get_matrix(GL_MODELVIEW_MATRIX));
        let mut probe = Probe {
            gl,
            at_spheres: Vec::new(),
        };
        let s = Scene {
            skeleton: &bvh.skeleton,
            frame: Some(frame),
            camera,
            style: Style::Points,
            offset_mode: Default::default(),
            skin: None,
            shown: None,
            sphere_radius: 1.0,
            up: bvhview::model::pose::Up::Y,
            origin: [0.0; 3],
            scale: 1.0,
            colours: None,
        };
        bvhview::render::draw::draw(&mut probe, s.skeleton, s.frame, s.style, s.offset_mode);
        let mut worlds = Vec::new();
        bvhview::model::pose::world_matrices(&bvh.skeleton, frame, Default::default(), &mut worlds);
        assert_eq!(probe.at_spheres.len(), worlds.len());
        for (i, (gl_matrix, world)) in probe.at_spheres.iter().zip(&worlds).enumerate() {
            let expected = view * *world;
            let got = glam::Mat4::from_cols_array(gl_matrix);
            assert!(
                got.abs_diff_eq(expected, 2e-3),
                "{name} joint {i}: {got} vs {expected}"
            );
        }
    }
}

/// `--style` and `--fit` change the picture; the default stays the article's.
#[test]
fn sticks_and_fit_are_opt_in() {
    let bvh = bvhview::bvh::load_file(&oracle_input("tiny_crlf.bvh"), Default::default()).unwrap();
    let base = SnapshotOptions {
        frame: 1,
        ..SnapshotOptions::default()
    };
    let article = bvhview::render::snapshot(&bvh.skeleton, &bvh.motion, &base).unwrap();
    let theirs = Image::read_png(&oracle("refs/tiny_crlf__f1__a10__600x600.png")).unwrap();
    assert_eq!(article.differing_pixels(&theirs), 0);
    let green = |image: &Image| {
        image
            .rgb
            .chunks_exact(3)
            .filter(|p| p[1] > 200 && p[0] < 50 && p[2] < 50)
            .count()
    };
    assert_eq!(green(&article), 0, "the article's picture has no green");
    let sticks = bvhview::render::snapshot(
        &bvh.skeleton,
        &bvh.motion,
        &SnapshotOptions {
            style: Style::Both,
            ..base
        },
    )
    .unwrap();
    assert!(
        green(&sticks) > 500,
        "the stick figure is green: {}",
        green(&sticks)
    );
}

/// init, reshape and display make exactly the calls the article's program makes, in order and
/// with the same arguments (tests/oracle/trace, recorded with apitrace).
#[test]
fn calls_match_the_articles_trace() {
    use bvhview::render::trace::{Numbers, Recorder};
    let bvh = bvhview::bvh::load_file(&oracle_input("tiny_crlf.bvh"), Default::default()).unwrap();
    let mut recorder = Recorder::new(Numbers::Apitrace);
    let camera = Camera::default();
    scene::init(&mut recorder);
    scene::reshape(&mut recorder, 600, 600, &camera);
    let s = Scene {
        skeleton: &bvh.skeleton,
        frame: Some(bvh.motion.frame(1)),
        camera,
        style: Style::Points,
        offset_mode: Default::default(),
        skin: None,
        shown: None,
        sphere_radius: 1.0,
        up: bvhview::model::pose::Up::Y,
        origin: [0.0; 3],
        scale: 1.0,
        colours: None,
    };
    scene::display(&mut recorder, &s);
    let expected = std::fs::read_to_string(oracle("trace/tiny_crlf__f1__a10.txt")).unwrap();
    let expected: Vec<&str> = expected.lines().collect();
    assert_eq!(recorder.lines.len(), expected.len());
    for (i, (ours, theirs)) in recorder.lines.iter().zip(&expected).enumerate() {
        assert_eq!(ours, theirs, "call {}", i + 1);
    }
}
