//! `cargo run --release -p bvhview-bench -- BIG.bvh [--quick]`: throughput of loading (bvhview
//! and bvh_anim 0.4 on the same bytes), forward kinematics, CSV export and offscreen drawing.
//!
//! `cargo run --release -p bvhview-bench -- --folder DIR`: load + world positions of every .bvh
//! file of a folder, the first pass of a fresh process against the best of later passes, with
//! the page faults of each: what a cold process pays that a warm one does not.

use std::time::{Duration, Instant};

/// The fastest of `runs` timings of `f` (the least disturbed by the rest of the machine).
fn best<T>(runs: usize, mut f: impl FnMut() -> T) -> (Duration, T) {
    let mut fastest = Duration::MAX;
    let mut last = None;
    for _ in 0..runs {
        let start = Instant::now();
        let value = f();
        fastest = fastest.min(start.elapsed());
        last = Some(value);
    }
    (fastest, last.expect("at least one run"))
}

fn mb_per_s(bytes: usize, time: Duration) -> f64 {
    bytes as f64 / 1e6 / time.as_secs_f64()
}

/// Minor page faults of this process so far (each first write to a fresh page is one); `None`
/// where the system does not count them for us.
#[cfg(unix)]
fn page_faults() -> Option<i64> {
    // SAFETY: getrusage only writes the struct it is given.
    unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        (libc::getrusage(libc::RUSAGE_SELF, &mut usage) == 0).then_some(usage.ru_minflt)
    }
}

#[cfg(not(unix))]
fn page_faults() -> Option<i64> {
    None
}

/// Prints what is wrong and how the bench is called, and exits 2.
fn usage_error(message: &str) -> ! {
    eprintln!(
        "bvhview-bench: {message}\n\
         usage: bvhview-bench BIG.bvh [--quick]   (make one: cargo run --release --example make_big -- SOURCE.bvh BIG.bvh 100)\n\
         \x20      bvhview-bench --folder DIR"
    );
    std::process::exit(2);
}

/// Prints an error about the input and exits 1.
fn input_error(message: impl std::fmt::Display) -> ! {
    eprintln!("bvhview-bench: {message}");
    std::process::exit(1);
}

/// One pass over `files`: load on every core (as `bvhview.load` does), then positions of every
/// frame on one core, kept until the pass ends (as a script keeping its arrays would). Returns
/// load time, positions time and page faults.
fn folder_pass(files: &[std::path::PathBuf]) -> (Duration, Duration, Option<i64>) {
    use bvhview::pose::{FkPlan, FkScratch, LANES, OffsetMode};
    let (mut load, mut positions) = (Duration::ZERO, Duration::ZERO);
    let faults = page_faults();
    let mut kept = Vec::new();
    for file in files {
        let start = Instant::now();
        let loaded = bvhview::input::load_checked(file, None, None, bvhview::cores(), u64::MAX)
            .unwrap_or_else(|e| input_error(e));
        let loaded_at = Instant::now();
        let plan = FkPlan::new(&loaded.skeleton, OffsetMode::Replace);
        let (mut points, mut scratch) = (Vec::new(), FkScratch::default());
        let mut out =
            Vec::with_capacity(loaded.motion.frame_count() * loaded.skeleton.joints.len());
        let frames: Vec<usize> = (0..loaded.motion.frame_count()).collect();
        for batch in frames.chunks(LANES) {
            let rows: Vec<&[f32]> = batch.iter().map(|&f| loaded.motion.frame(f)).collect();
            plan.positions_of_frames(&rows, &mut points, &mut scratch);
            out.extend_from_slice(&points);
        }
        positions += loaded_at.elapsed();
        load += loaded_at - start;
        kept.push((loaded, out));
    }
    let faults = page_faults()
        .zip(faults)
        .map(|(after, before)| after - before);
    (load, positions, faults)
}

fn folder(dir: &str) {
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| input_error(format!("{dir}: {e}")))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| {
            path.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("bvh"))
        })
        .collect();
    files.sort();
    let bytes: u64 = files
        .iter()
        .filter_map(|f| f.metadata().ok())
        .map(|m| m.len())
        .sum();
    println!(
        "folder: {dir} ({} files, {:.1} MB), {} cores",
        files.len(),
        bytes as f64 / 1e6,
        bvhview::cores()
    );
    if files.is_empty() {
        input_error(format!("{dir}: no .bvh file in it"));
    }
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let counted = |faults: Option<i64>| {
        faults.map_or("page faults not counted here".into(), |n| {
            format!("{n} page faults")
        })
    };
    let (load, positions, faults) = folder_pass(&files);
    println!(
        "first pass (fresh process): load {:.2} ms + positions {:.2} ms = {:.2} ms, {}",
        ms(load),
        ms(positions),
        ms(load + positions),
        counted(faults)
    );
    let later = (0..10)
        .map(|_| folder_pass(&files))
        .min_by_key(|(l, p, _)| *l + *p);
    let (load, positions, faults) = later.expect("ten passes");
    println!(
        "best of 10 later passes:   load {:.2} ms + positions {:.2} ms = {:.2} ms, {}",
        ms(load),
        ms(positions),
        ms(load + positions),
        counted(faults)
    );
}

fn main() {
    let (mut folder_dir, mut file, mut quick) = (None, None, false);
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--folder" => match args.next() {
                Some(dir) if !dir.starts_with("--") => folder_dir = Some(dir),
                _ => usage_error("--folder needs a folder"),
            },
            "--quick" => quick = true,
            option if option.starts_with("--") => usage_error(&format!("no option {option}")),
            _ if file.is_some() => usage_error("one BIG.bvh at a time"),
            _ => file = Some(arg),
        }
    }
    match (folder_dir, file) {
        (Some(_), Some(path)) => usage_error(&format!("--folder or {path}, not both")),
        (Some(_), None) if quick => usage_error("--quick is for BIG.bvh, not --folder"),
        (Some(dir), None) => folder(&dir),
        (None, Some(path)) => big(&path, quick),
        (None, None) => usage_error("no file given"),
    }
}

/// Every throughput of the bench on one big file.
fn big(path: &str, quick: bool) {
    let runs = if quick { 2 } else { 7 };
    let bytes = std::fs::read(path).unwrap_or_else(|e| input_error(format!("{path}: {e}")));
    if let Err(e) = bvhview::bvh::load_bytes(&bytes, path) {
        input_error(e);
    }
    let size = bytes.len();
    println!(
        "file: {path} ({:.1} MB), {} cores",
        size as f64 / 1e6,
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );

    // Loading.
    let (t_file, bvh) = best(runs, || {
        bvhview::bvh::load_file(std::path::Path::new(path), Default::default()).expect("loads")
    });
    let (t_one, _) = best(runs, || {
        bvhview::bvh::load_file(
            std::path::Path::new(path),
            bvhview::bvh::loader::Settings {
                threads: 1,
                ..Default::default()
            },
        )
        .expect("loads")
    });
    let (t_bytes, _) = best(runs, || {
        bvhview::bvh::load_bytes(&bytes, path).expect("loads")
    });
    let joints = bvh.skeleton.joints.len();
    let frames = bvh.motion.frame_count();
    println!(
        "load_file   (from the page cache): {:8.1} ms  {:7.1} MB/s",
        t_file.as_secs_f64() * 1e3,
        mb_per_s(size, t_file)
    );
    println!(
        "load_file   on one thread:         {:8.1} ms  {:7.1} MB/s",
        t_one.as_secs_f64() * 1e3,
        mb_per_s(size, t_one)
    );
    println!(
        "load_bytes  (from memory):         {:8.1} ms  {:7.1} MB/s",
        t_bytes.as_secs_f64() * 1e3,
        mb_per_s(size, t_bytes)
    );
    let text = std::str::from_utf8(&bytes).expect("UTF-8");
    let anim_runs = if quick { 1 } else { 3 };
    let (t_anim, anim) = best(anim_runs, || {
        bvh_anim::from_str(text).expect("bvh_anim loads")
    });
    println!(
        "bvh_anim 0.4 from_str:             {:8.1} ms  {:7.1} MB/s",
        t_anim.as_secs_f64() * 1e3,
        mb_per_s(size, t_anim)
    );
    drop(anim);
    println!(
        "bvhview / bvh_anim:                {:8.1}x",
        t_anim.as_secs_f64() / t_file.as_secs_f64()
    );

    // Forward kinematics: world position of every joint on every frame.
    let (t_fk, checksum) = best(runs, || {
        bvhview::pose::positions_all_frames(
            &bvh.skeleton,
            &bvh.motion,
            bvhview::pose::OffsetMode::Replace,
        )
    });
    let transforms = joints * frames;
    println!(
        "FK, all frames:                    {:8.1} ms  {:7.1} M joint transforms/s ({joints} joints × {frames} frames, checksum {checksum:.3})",
        t_fk.as_secs_f64() * 1e3,
        transforms as f64 / 1e6 / t_fk.as_secs_f64()
    );

    // CSV export to memory.
    let options = bvhview::export::PositionsOptions::default();
    let (t_csv, written) = best(runs.min(3), || {
        let mut out = Vec::with_capacity(1 << 30);
        bvhview::export::write_positions(&mut out, &bvh.skeleton, &bvh.motion, 0..frames, &options)
            .expect("writes");
        out.len()
    });
    println!(
        "positions CSV:                     {:8.1} ms  {:7.1} MB/s of output ({:.0} MB)",
        t_csv.as_secs_f64() * 1e3,
        mb_per_s(written, t_csv),
        written as f64 / 1e6
    );

    // Drawing, offscreen at the article's 600×600.
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/bvh");
    for (name, file) in [
        ("CMU 31 joints", "assimp_01_01.bvh"),
        ("MakeHuman 173 joints", "makehuman_tpose.bvh"),
    ] {
        let rig = match bvhview::bvh::load_file(&data.join(file), Default::default()) {
            Ok(rig) => rig,
            Err(e) => {
                println!("draw {name}: skipped ({e})");
                continue;
            }
        };
        let mut renderer =
            bvhview::render::Renderer::new(600, 600).expect("OSMesa (apt-get install libosmesa6)");
        let frames = rig.motion.frame_count();
        let draws = if quick { 5 } else { 30 };
        // Each frame of the take in turn, with or without the skin: the mean time per frame.
        let mut time_draws = |skin: bool| {
            let start = Instant::now();
            for i in 0..draws {
                let options = bvhview::render::SnapshotOptions {
                    frame: i % frames,
                    skin,
                    ..Default::default()
                };
                renderer
                    .render(&rig.skeleton, &rig.motion, &options)
                    .expect("draws");
            }
            start.elapsed() / draws as u32
        };
        let per = time_draws(false);
        println!(
            "draw + read back, 600×600, {name}: {:6.2} ms per frame",
            per.as_secs_f64() * 1e3
        );

        // The generated skin: posing it (FK + linear blend skinning) alone, then the whole frame.
        let body =
            bvhview::render::body::Body::new(&rig.skeleton, bvhview::pose::OffsetMode::Replace);
        let (mut posed, mut scratch) = (
            bvhview::render::body::PosedBody::default(),
            (Vec::new(), Vec::new()),
        );
        let poses = if quick { 50 } else { 500 };
        let start = Instant::now();
        for i in 0..poses {
            body.pose(
                &rig.skeleton,
                Some(rig.motion.frame(i % frames)),
                &mut posed,
                &mut scratch,
            );
        }
        let pose = start.elapsed() / poses as u32;
        let skinned = time_draws(true);
        println!(
            "  skin ({} vertices): pose {:.3} ms, frame with skin {:.2} ms ({:.0} frames/s)",
            body.skin.vertices.len(),
            pose.as_secs_f64() * 1e3,
            skinned.as_secs_f64() * 1e3,
            1.0 / skinned.as_secs_f64()
        );
    }
}
