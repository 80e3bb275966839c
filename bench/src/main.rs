//! `cargo run --release -p bvhview-bench -- BIG.bvh [--quick] [--rounds N] [--no-avx512]
//! [--article PROGRAM]`: loading the same file with bvhview (one thread and every thread),
//! bvh_anim 0.4, a naive reader (split on whitespace, fast-float2) and the article's own loader
//! (built from its text by `bench/article.py`), interleaved round-robin, median and fastest of
//! each; then forward kinematics, CSV export and offscreen drawing.
//!
//! `cargo run --release -p bvhview-bench -- --folder DIR`: load + world positions of every .bvh
//! file of a folder, the first pass of a fresh process against the best of later passes, with
//! the page faults of each: what a cold process pays that a warm one does not.
//!
//! `cargo run --release -p bvhview-bench -- --encoders`: GIF, APNG and MP4 (H.264) encoding of
//! the same pictures, alone (the full run includes it).
//!
//! `cargo run --release -p bvhview-bench -- --writers FILE [--rounds N]`: the same take written
//! as BVH, glTF (.glb) and FBX into memory on one thread, interleaved round-robin, median and
//! fastest of each, in nanoseconds a frame-value (frames × channels).
//!
//! `cargo run --release -p bvhview-bench -- --amass FEATURES.npy [--rounds N]`: HumanML3D's
//! feature vectors to AMASS's `.npz` in memory, as `solve --from humanml3d --onto smpl22 -o
//! out.npz` does (positions recovered, rotations solved, axis-angles written), on one thread,
//! the clip repeated to 10,000 frames: frames a second, median and fastest.
//!
//! `cargo run --release -p bvhview-bench -- --keypoints TAKE [--rounds N]`: a take's joints as
//! each keypoint layout's points (as `positions --layout` writes them), then read back as
//! `solve --layout` reads them (points to roles, missing joints placed, the figure stood up) and
//! solved onto the take's own skeleton, on one thread, the take repeated to 10,000 frames: frames
//! a second per layout, median and fastest.
//!
//! `cargo run --release -p bvhview-bench -- --skinning [CHARACTER]`: linear blend skinning of
//! the committed characters, of capsule man ten times over (29,040 vertices in one place) and of
//! CHARACTER (the 30,888-vertex `capsule_fine.glb` of `tests/blender/make_capsule_character.py
//! --fine`), vertex-influences a second on one core; then each drawn with the CMU walk on it.

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
         usage: bvhview-bench BIG.bvh [--quick] [--rounds N] [--no-avx512] [--article PROGRAM]\n\
         \x20      (make BIG.bvh: cargo run --release --example make_big -- SOURCE.bvh BIG.bvh 100)\n\
         \x20      bvhview-bench BIG.bvh --one-core [--rounds N]   (only the one-core rows)\n\
         \x20      bvhview-bench --folder DIR\n\
         \x20      bvhview-bench --encoders   (GIF, APNG and MP4 encoding only)"
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
    use bvhview::model::pose::{FkPlan, FkScratch, LANES, OffsetMode};
    let (mut load, mut positions) = (Duration::ZERO, Duration::ZERO);
    let faults = page_faults();
    let mut kept = Vec::new();
    for file in files {
        let start = Instant::now();
        let loaded = bvhview::take::OpenOptions::new()
            .max_size(u64::MAX)
            .open(file)
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
        bvhview::plumbing::cores()
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
    let (mut folder_dir, mut file, mut quick, mut only_one_core) = (None, None, false, false);
    let mut load = LoadOptions::default();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--folder" => match args.next() {
                Some(dir) if !dir.starts_with("--") => folder_dir = Some(dir),
                _ => usage_error("--folder needs a folder"),
            },
            "--quick" => quick = true,
            "--one-core" => only_one_core = true,
            "--encoders" => {
                println!("cpu: {}", cpu_description());
                return compare_encoders(false);
            }
            "--skinning" => {
                println!("cpu: {}", cpu_description());
                // An extra character (the 30,000-vertex one) may follow.
                let extra: Vec<String> = args.by_ref().collect();
                return skinning(7, extra.first().map(String::as_str));
            }
            "--writers" => match args.next() {
                Some(path) if !path.starts_with("--") => {
                    let rounds = rounds_after(&mut args, "--writers FILE [--rounds N]");
                    println!("cpu: {}", cpu_description());
                    return compare_writers(&path, rounds);
                }
                _ => usage_error("--writers needs a take"),
            },
            "--amass" => match args.next() {
                Some(path) if !path.starts_with("--") => {
                    let rounds = rounds_after(&mut args, "--amass FEATURES.npy [--rounds N]");
                    println!("cpu: {}", cpu_description());
                    return humanml3d_to_amass(&path, rounds);
                }
                _ => usage_error("--amass needs HumanML3D feature vectors (.npy)"),
            },
            "--keypoints" => match args.next() {
                Some(path) if !path.starts_with("--") => {
                    let rounds = rounds_after(&mut args, "--keypoints TAKE [--rounds N]");
                    println!("cpu: {}", cpu_description());
                    return keypoints(&path, rounds);
                }
                _ => usage_error("--keypoints needs a take"),
            },
            "--in-process" => match (args.next(), args.next()) {
                (Some(what), Some(path)) => return in_process(&what, &path),
                _ => usage_error("--in-process needs info|positions|dataset and a file"),
            },
            "--no-avx512" => bvhview::bvh::rows::read_one_at_a_time(true),
            "--rounds" => match args.next().and_then(|n| n.parse().ok()) {
                Some(n) if n > 0 => load.rounds = Some(n),
                _ => usage_error("--rounds needs a number of rounds above 0"),
            },
            "--article" => match args.next() {
                Some(program) => load.article = Some(program),
                None => usage_error("--article needs the program bench/article.py built"),
            },
            option if option.starts_with("--") => usage_error(&format!("no option {option}")),
            _ if file.is_some() => usage_error("one BIG.bvh at a time"),
            _ => file = Some(arg),
        }
    }
    match (folder_dir, file) {
        (Some(_), Some(path)) => usage_error(&format!("--folder or {path}, not both")),
        (Some(_), None) if quick => usage_error("--quick is for BIG.bvh, not --folder"),
        (Some(dir), None) => {
            folder(&dir);
            dataset_stages(&dir, load.rounds.unwrap_or(5));
            humanml3d_against_onto(&dir, load.rounds.unwrap_or(5));
        }
        (None, Some(path)) if only_one_core => {
            println!("cpu: {}", cpu_description());
            one_core(&path, load.rounds.unwrap_or(5));
        }
        (None, Some(path)) => big(&path, quick, &load),
        (None, None) => usage_error("no file given"),
    }
}

/// HumanML3D's vectors at `path` (repeated to 10,000 frames) to AMASS's `.npz` on one thread,
/// `rounds` times: frames a second, median and fastest.
fn humanml3d_to_amass(path: &str, rounds: usize) {
    const FRAMES: usize = 10_000;
    let bytes = std::fs::read(path).unwrap_or_else(|e| input_error(format!("{path}: {e}")));
    let clip = bvhview::humanml3d::read_vectors(&bytes, path).unwrap_or_else(|e| input_error(e));
    let width = bvhview::humanml3d::WIDTH;
    let clip_frames = clip.len() / width;
    if clip_frames == 0 {
        input_error(format!("{path}: no frames"));
    }
    let vectors: Vec<f32> = clip
        .chunks_exact(width)
        .cycle()
        .take(FRAMES)
        .flatten()
        .copied()
        .collect();
    let target = bvhview::retarget::Target::load("smpl22", u64::MAX).expect("built in");
    let once = || {
        let points = bvhview::humanml3d::recover_from_ric(&vectors).expect("recovered");
        let positions = bvhview::solve::Positions::new(
            bvhview::solve::joint_names("smpl22"),
            points,
            1.0 / 20.0,
        )
        .expect("positions");
        let (motion, _, _) =
            bvhview::solve::solve_smoothed(&target.skeleton, target.up, &positions, None, None)
                .expect("solved");
        let take = bvhview::Take::new(target.skeleton.clone(), motion, "humanml3d");
        take.amass().expect("written").0.len()
    };
    let mut times = Vec::with_capacity(rounds);
    let mut written = 0;
    for _ in 0..rounds {
        let start = Instant::now();
        written = once();
        times.push(start.elapsed());
    }
    let (median, fastest) = median_and_min(&mut times);
    println!(
        "humanml3d → amass .npz, one thread: {FRAMES} frames ({clip_frames}-frame clip repeated), \
         {written} bytes; {:.0} frames/s median ({:.3} s), {:.0} fastest",
        FRAMES as f64 / median.as_secs_f64(),
        median.as_secs_f64(),
        FRAMES as f64 / fastest.as_secs_f64()
    );
}

/// Keypoints of every layout solved onto a take's skeleton, one thread (`--keypoints`).
fn keypoints(path: &str, rounds: usize) {
    use bvhview::solve::layouts::{Keypoints, Layout, of_take, onto_skeleton, to_smpl};
    const FRAMES: usize = 10_000;
    let take = bvhview::Take::open(path).unwrap_or_else(|e| input_error(e));
    let stance = take.stance(take.offset_mode);
    let metres = f64::from(stance.units.metres);
    for layout in Layout::ALL {
        let clip = of_take(&take, layout, metres).unwrap_or_else(|e| input_error(e));
        let count = layout.points().len();
        let clip_frames = clip.points.len() / count;
        let values: Vec<f64> = clip
            .points
            .chunks_exact(count)
            .zip(clip.confidence.chunks_exact(count))
            .cycle()
            .take(FRAMES)
            .flat_map(|(points, sure)| {
                points
                    .iter()
                    .zip(sure)
                    .flat_map(|(p, c)| [p.x, p.y, p.z, *c])
                    .collect::<Vec<_>>()
            })
            .collect();
        let once = || {
            let keypoints = Keypoints::new(layout, &[FRAMES, count, 4], &values, 1.0 / 30.0, "k")
                .expect("keypoints");
            let placed = to_smpl(&keypoints, 0.3, None, "k").expect("placed");
            let (positions, _) = onto_skeleton(&placed.positions, &take.skeleton).expect("renamed");
            let (motion, _) = bvhview::solve::solve(
                &take.skeleton,
                stance.up,
                &positions,
                Some(bvhview::model::pose::UpAxis::Y),
            )
            .expect("solved");
            motion.frame_count()
        };
        let mut times = Vec::with_capacity(rounds);
        for _ in 0..rounds {
            let start = Instant::now();
            assert_eq!(once(), FRAMES);
            times.push(start.elapsed());
        }
        let (median, fastest) = median_and_min(&mut times);
        println!(
            "{} keypoints → {path}'s skeleton, one thread: {FRAMES} frames ({clip_frames}-frame \
             take repeated); {:.0} frames/s median ({:.3} s), {:.0} fastest",
            layout.label(),
            FRAMES as f64 / median.as_secs_f64(),
            median.as_secs_f64(),
            FRAMES as f64 / fastest.as_secs_f64()
        );
    }
}

/// The rounds an option's file may be followed by (`--rounds N`, else 7); anything else is a
/// usage error that shows `usage`.
fn rounds_after(args: &mut impl Iterator<Item = String>, usage: &str) -> usize {
    let rounds = match (args.next().as_deref(), args.next()) {
        (Some("--rounds"), Some(n)) => n.parse().ok().filter(|&n| n > 0),
        (None, None) => Some(7),
        _ => None,
    };
    rounds.unwrap_or_else(|| usage_error(usage))
}

/// Every throughput of the bench on one big file.
fn big(path: &str, quick: bool, load: &LoadOptions) {
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
    println!("cpu: {}", cpu_description());
    println!("row reader: {}", bvhview::bvh::rows::row_reader());

    // Loading, every tool in turn in each round.
    let bvh = compare_loaders(path, &bytes, quick, load);
    let joints = bvh.skeleton.joints.len();
    let frames = bvh.motion.frame_count();

    // Forward kinematics: world position of every joint on every frame.
    let (t_fk, checksum) = best(runs, || {
        bvhview::model::pose::positions_all_frames(
            &bvh.skeleton,
            &bvh.motion,
            bvhview::model::pose::OffsetMode::Replace,
        )
    });
    let transforms = joints * frames;
    println!(
        "FK, all frames:                    {:8.1} ms  {:7.1} M joint transforms/s ({joints} joints × {frames} frames, checksum {checksum:.3})",
        t_fk.as_secs_f64() * 1e3,
        transforms as f64 / 1e6 / t_fk.as_secs_f64()
    );

    // Retargeting onto the built-in smpl22: FK plus a rotation per joint, against
    // loading the same file, thread for thread. Each round loads on one thread, retargets on one
    // thread, then the same on every thread; ratios are taken round by round.
    let target = bvhview::retarget::Target::load("smpl22", u64::MAX).expect("built in");
    let cores = bvhview::plumbing::cores();
    let rounds = load.rounds.unwrap_or(if quick { 3 } else { 5 });
    let file = std::path::Path::new(path);
    let retargets = target
        .apply(
            "BIG",
            &bvh.skeleton,
            &bvh.motion,
            &[],
            Default::default(),
            1,
        )
        .is_ok();
    if !retargets {
        println!("retarget onto smpl22: skipped: the file's skeleton has no human chain");
    }
    for threads in [1, cores] {
        if !retargets {
            break;
        }
        let settings = bvhview::bvh::loader::Settings {
            threads,
            ..Default::default()
        };
        let (mut loads, mut moves) = (Vec::new(), Vec::new());
        for _ in 0..rounds {
            let start = Instant::now();
            drop(bvhview::bvh::load_file(file, settings).expect("loads"));
            loads.push(start.elapsed());
            let start = Instant::now();
            let moved = target.apply(
                "BIG",
                &bvh.skeleton,
                &bvh.motion,
                &[],
                Default::default(),
                threads,
            );
            moves.push(start.elapsed());
            drop(moved);
        }
        let mut ratios: Vec<f64> = moves
            .iter()
            .zip(&loads)
            .map(|(m, l)| m.as_secs_f64() / l.as_secs_f64())
            .collect();
        ratios.sort_by(f64::total_cmp);
        let (lm, lf) = median_and_min(&mut loads);
        let (rm, rf) = median_and_min(&mut moves);
        println!(
            "retarget onto smpl22 against load, {threads} thread(s), {rounds} rounds in turn: \
             load median {:.1} ms (fastest {:.1}), retarget median {:.1} ms (fastest {:.1}, {:.1} MB/s of input); \
             retarget/load pair by pair: median {:.3} (from {:.3} to {:.3})",
            lm.as_secs_f64() * 1e3,
            lf.as_secs_f64() * 1e3,
            rm.as_secs_f64() * 1e3,
            rf.as_secs_f64() * 1e3,
            mb_per_s(size, rm),
            ratios[ratios.len() / 2],
            ratios[0],
            ratios[ratios.len() - 1]
        );
    }

    // Joint positions back to rotations: the take's 22 joints on smpl22, as a
    // motion model outputs them, solved back onto smpl22 on one thread, in turn with
    // retargeting the take there on one thread, round by round.
    if retargets {
        use bvhview::model::pose::{OffsetMode, world_transforms_f64};
        let put = target
            .apply(
                "BIG",
                &bvh.skeleton,
                &bvh.motion,
                &[],
                Default::default(),
                1,
            )
            .expect("retargets");
        let (smpl, moved) = (put.skeleton, put.motion);
        let names: Vec<String> = (0..smpl.joints.len())
            .map(|j| bvhview::model::skeleton::export_name(&smpl, j))
            .collect();
        let order: Vec<usize> = bvhview::solve::SMPL22_ORDER
            .iter()
            .map(|n| names.iter().position(|m| m == n).expect("smpl22 names"))
            .collect();
        let mut points = Vec::with_capacity(moved.frame_count() * order.len());
        let mut world = Vec::new();
        for f in 0..moved.frame_count() {
            world_transforms_f64(&smpl, moved.frame(f), OffsetMode::Replace, &mut world);
            points.extend(order.iter().map(|&j| world[j].1));
        }
        let positions = bvhview::solve::Positions::new(
            bvhview::solve::joint_names("smpl22"),
            points,
            moved.frame_time,
        )
        .expect("finite positions");
        let (mut solves, mut moves) = (Vec::new(), Vec::new());
        for _ in 0..rounds {
            let start = Instant::now();
            drop(target.apply(
                "BIG",
                &bvh.skeleton,
                &bvh.motion,
                &[],
                Default::default(),
                1,
            ));
            moves.push(start.elapsed());
            let start = Instant::now();
            drop(bvhview::solve::solve(&smpl, target.up, &positions, None).expect("solves"));
            solves.push(start.elapsed());
        }
        let (sm, sf) = median_and_min(&mut solves);
        let (rm, rf) = median_and_min(&mut moves);
        let frames = moved.frame_count() as f64;
        println!(
            "solve 22 joints onto smpl22, 1 thread, {rounds} rounds in turn with retarget: \
             solve median {:.1} ms (fastest {:.1}), {:.0} frames/s per core (fastest {:.0}); \
             retarget median {:.1} ms (fastest {:.1})",
            sm.as_secs_f64() * 1e3,
            sf.as_secs_f64() * 1e3,
            frames / sm.as_secs_f64(),
            frames / sf.as_secs_f64(),
            rm.as_secs_f64() * 1e3,
            rf.as_secs_f64() * 1e3,
        );
    }

    // CSV export to memory.
    let options = bvhview::positions::PositionsOptions::default();
    let (t_csv, written) = best(runs.min(3), || {
        let mut out = Vec::with_capacity(1 << 30);
        bvhview::positions::write_positions(
            &mut out,
            &bvh.skeleton,
            &bvh.motion,
            0..frames,
            &options,
        )
        .expect("writes");
        out.len()
    });
    println!(
        "positions CSV:                     {:8.1} ms  {:7.1} MB/s of output ({:.0} MB)",
        t_csv.as_secs_f64() * 1e3,
        mb_per_s(written, t_csv),
        written as f64 / 1e6
    );

    // The dataset's stages, then each command on one core against the same work in process.
    dataset_stages(path, if quick { 3 } else { 5 });
    if retargets {
        humanml3d_against_onto(path, if quick { 3 } else { 5 });
    }
    one_core(path, load.rounds.unwrap_or(if quick { 3 } else { 5 }));

    // A sequence of pictures (`snapshot --frames`) against the article's display() alone.
    compare_sequences(quick);
    // The same pictures encoded as GIF, APNG and MP4 video.
    compare_encoders(quick);

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
        let body = bvhview::model::bone_skin::Body::new(
            &rig.skeleton,
            bvhview::model::pose::OffsetMode::Replace,
        );
        let (mut posed, mut scratch) = (
            bvhview::model::bone_skin::PosedBody::default(),
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

/// What the load comparison runs besides the file.
#[derive(Default)]
struct LoadOptions {
    /// Rounds of every tool in turn (default 7, 3 with --quick).
    rounds: Option<usize>,
    /// The article's loader (default: built by `bench/article.py` from the article's text beside
    /// the checkout): it prints the seconds its `loadFile` took.
    article: Option<String>,
}

/// The CPU's model and the vector extensions the row reader cares about, from /proc/cpuinfo.
fn cpu_description() -> String {
    let info = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let field = |name: &str| {
        info.lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_once(':'))
            .map(|(_, v)| v.trim().to_string())
            .unwrap_or_default()
    };
    let flags = field("flags");
    let wanted = [
        "avx2",
        "avx512f",
        "avx512bw",
        "avx512cd",
        "avx512vl",
        "avx512vbmi",
    ];
    let present: Vec<&str> = wanted
        .into_iter()
        .filter(|f| flags.split(' ').any(|x| x == *f))
        .collect();
    let absent: Vec<&str> = wanted
        .into_iter()
        .filter(|f| !flags.split(' ').any(|x| x == *f))
        .collect();
    format!(
        "{}; has {}; lacks {}",
        field("model name"),
        present.join(" "),
        if absent.is_empty() {
            "none of those".to_string()
        } else {
            absent.join(" ")
        }
    )
}

/// The naive floor: the MOTION text split on whitespace, each word parsed by fast-float2, no
/// checks beyond that. Returns the values read.
fn naive_floor(bytes: &[u8]) -> Vec<f32> {
    let text = std::str::from_utf8(bytes).expect("UTF-8");
    let at = text.find("Frame Time:").expect("a MOTION section");
    let rows = &text[at..];
    let rows = &rows[rows.find('\n').map_or(rows.len(), |n| n + 1)..];
    let mut values = Vec::with_capacity(rows.len() / 7);
    for word in rows.split_ascii_whitespace() {
        values.push(fast_float2::parse::<f32, _>(word).expect("a number"));
    }
    values
}

/// The article's loader, built by `bench/article.py` from the article's text beside the checkout
/// (`../shared/seeds/000_*.txt`), into a temporary folder; `None` when the text is not there or
/// the build fails (said on stderr).
fn build_article() -> Option<String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let seeds = root.join("../shared/seeds");
    let seed = std::fs::read_dir(&seeds)
        .ok()?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("000_"))
        })?;
    let out = std::env::temp_dir().join(format!("bvhview-article-{}", std::process::id()));
    let built = std::process::Command::new("python3")
        .arg(root.join("bench/article.py"))
        .arg(&seed)
        .arg(&out)
        .output();
    match built {
        Ok(built) if built.status.success() => {
            Some(String::from_utf8_lossy(&built.stdout).trim().to_string())
        }
        Ok(built) => {
            eprintln!(
                "bvhview-bench: building the article's loader failed: {}",
                String::from_utf8_lossy(&built.stderr)
            );
            None
        }
        Err(e) => {
            eprintln!("bvhview-bench: python3 bench/article.py: {e}");
            None
        }
    }
}

/// One load by the article's program: the seconds it reports for `loadFile`, or what it printed
/// instead (it loads only the layout it was written for: CR LF, a blank after each row…).
fn try_article(program: &str, path: &str) -> Result<Duration, String> {
    let out = std::process::Command::new(program)
        .arg(path)
        .output()
        .map_err(|e| format!("{program}: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout);
    text.lines()
        .find_map(|l| l.strip_prefix("loadFile seconds: "))
        .and_then(|v| v.trim().parse().ok())
        .map(Duration::from_secs_f64)
        .ok_or_else(|| text.trim().replace('\n', " "))
}

fn article_seconds(program: &str, path: &str) -> Duration {
    try_article(program, path).unwrap_or_else(|e| input_error(e))
}

/// BVH, glTF and FBX out of the take at `path`, into memory on one thread, each writer in turn
/// in every round: each one's median and fastest in nanoseconds a frame-value, and FBX's pace
/// against BVH's (above 1: FBX out is faster a value than BVH out).
fn compare_writers(path: &str, rounds: usize) {
    let take = bvhview::Take::open(path).unwrap_or_else(|e| input_error(e));
    let values = (take.motion.frame_count() * take.motion.channels).max(1);
    println!(
        "take: {path} ({} joints, {} frames, {values} frame-values), one thread, {rounds} rounds",
        take.skeleton.joints.len(),
        take.motion.frame_count()
    );
    type Writer<'a> = (&'a str, Box<dyn Fn() -> usize + 'a>);
    let writers: Vec<Writer> = vec![
        (
            "BVH",
            Box::new(|| {
                take.bvh_text()
                    .map(|t| t.len())
                    .unwrap_or_else(|e| input_error(e))
            }),
        ),
        (
            "glTF (.glb)",
            Box::new(|| {
                take.gltf(bvhview::gltf::Container::Glb)
                    .map(|b| b.len())
                    .unwrap_or_else(|e| input_error(e))
            }),
        ),
        (
            "FBX",
            Box::new(|| {
                take.fbx()
                    .map(|w| w.bytes.len())
                    .unwrap_or_else(|e| input_error(e))
            }),
        ),
    ];
    let mut times = vec![Vec::new(); writers.len()];
    let mut sizes = vec![0; writers.len()];
    for _ in 0..rounds {
        for (k, (_, write)) in writers.iter().enumerate() {
            let start = Instant::now();
            sizes[k] = write();
            times[k].push(start.elapsed());
        }
    }
    let per_value = |d: Duration| d.as_secs_f64() * 1e9 / values as f64;
    let mut medians = Vec::new();
    for (k, (name, _)) in writers.iter().enumerate() {
        let (median, fastest) = median_and_min(&mut times[k]);
        medians.push(median);
        println!(
            "{name:12} median {:7.2} ns a value, fastest {:7.2} ({:.1} MB)",
            per_value(median),
            per_value(fastest),
            sizes[k] as f64 / 1e6
        );
    }
    println!(
        "FBX's pace against BVH's (medians): {:.2}x",
        medians[0].as_secs_f64() / medians[2].as_secs_f64()
    );
}

/// The median and the fastest of some timings.
fn median_and_min(times: &mut [Duration]) -> (Duration, Duration) {
    times.sort();
    (times[times.len() / 2], times[0])
}

/// Loads `path` with every tool, one after the other in each round, and prints each tool's
/// median and fastest time, then bvhview's ratios thread for thread (its one thread against
/// each tool, all of which read on one thread) and on all threads. Returns bvhview's take.
fn compare_loaders(
    path: &str,
    bytes: &[u8],
    quick: bool,
    options: &LoadOptions,
) -> bvhview::bvh::Bvh {
    let rounds = options.rounds.unwrap_or(if quick { 3 } else { 7 });
    let cores = bvhview::plumbing::cores();
    let file = std::path::Path::new(path);
    let one = bvhview::bvh::loader::Settings {
        threads: 1,
        ..Default::default()
    };
    let article = options.article.clone().or_else(build_article);
    let article = article.filter(|program| match try_article(program, path) {
        Ok(_) => true,
        Err(said) => {
            println!("(the article's loadFile cannot read this file: {said})");
            false
        }
    });
    type Tool<'a> = (&'a str, bool, Box<dyn FnMut() -> Duration + 'a>);
    let timed = |f: &mut dyn FnMut()| {
        let start = Instant::now();
        f();
        start.elapsed()
    };
    let mut tools: Vec<Tool> = vec![
        (
            "bvhview, 1 thread",
            true,
            Box::new(move || {
                timed(&mut || drop(bvhview::bvh::load_file(file, one).expect("loads")))
            }),
        ),
        (
            "bvhview, all threads",
            false,
            Box::new(move || {
                timed(&mut || {
                    drop(bvhview::bvh::load_file(file, Default::default()).expect("loads"))
                })
            }),
        ),
        (
            "bvh_anim 0.4, 1 thread",
            true,
            Box::new(move || {
                timed(&mut || {
                    let text = std::fs::read_to_string(file).expect("reads");
                    drop(bvh_anim::from_str(&text).expect("bvh_anim loads"));
                })
            }),
        ),
        (
            "naive floor, 1 thread",
            true,
            Box::new(move || {
                timed(&mut || {
                    let bytes = std::fs::read(file).expect("reads");
                    drop(naive_floor(&bytes));
                })
            }),
        ),
    ];
    if let Some(program) = &article {
        tools.push((
            "the article's loadFile, 1 thread",
            true,
            Box::new(move || article_seconds(program, path)),
        ));
    }
    // Both read every value of the file.
    let ours = bvhview::bvh::load_bytes(bytes, path).expect("loads");
    assert_eq!(
        naive_floor(bytes).len(),
        ours.motion.data.len(),
        "the floor reads every value"
    );
    let mut times: Vec<Vec<Duration>> = vec![Vec::new(); tools.len()];
    for _ in 0..rounds {
        for (index, (_, _, run)) in tools.iter_mut().enumerate() {
            times[index].push(run());
        }
    }
    println!("load, {rounds} rounds of every tool in turn ({cores} cores; median and fastest):");
    let medians: Vec<(Duration, Duration)> = times.iter_mut().map(|t| median_and_min(t)).collect();
    for ((name, _, _), (median, min)) in tools.iter().zip(&medians) {
        println!(
            "  {name:34} median {:8.1} ms {:7.1} MB/s   fastest {:8.1} ms {:7.1} MB/s",
            median.as_secs_f64() * 1e3,
            mb_per_s(bytes.len(), *median),
            min.as_secs_f64() * 1e3,
            mb_per_s(bytes.len(), *min)
        );
    }
    let ratio = |ours: usize, theirs: usize| {
        (
            medians[theirs].0.as_secs_f64() / medians[ours].0.as_secs_f64(),
            medians[theirs].1.as_secs_f64() / medians[ours].1.as_secs_f64(),
        )
    };
    for (index, (name, single, _)) in tools.iter().enumerate().skip(2) {
        if *single {
            let (m1, f1) = ratio(0, index);
            let (ma, fa) = ratio(1, index);
            println!(
                "  bvhview / {name}: thread for thread {m1:.2}x (fastest {f1:.2}x); all {cores} threads {ma:.2}x (fastest {fa:.2}x)"
            );
        }
    }
    ours
}

/// `snapshot --frames 0..N` of the CMU take at 600×600 into PNG files (drawn here, encoded and
/// written on the other core) against the article's `display()` of the same frames on the same
/// Mesa (its GL calls as the port issues them, then glFinish: what its window waits for),
/// interleaved round-robin. Per frame, median and fastest of the rounds.
fn compare_sequences(quick: bool) {
    use bvhview::render::scene::{self, Camera, Scene};
    use bvhview::render::{Renderer, SnapshotOptions, animation, paint::Shown};
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/bvh/assimp_01_01.bvh");
    let Ok(take) = bvhview::Take::open(&file) else {
        println!("sequence: skipped (no {})", file.display());
        return;
    };
    let (rounds, count) = if quick { (3, 50) } else { (7, 200) };
    let out = std::env::temp_dir().join(format!("bvhview-bench-frames-{}", std::process::id()));
    std::fs::create_dir_all(&out).expect("a temporary folder");
    let mut renderer = Renderer::new(600, 600).expect("OSMesa (apt-get install libosmesa6)");
    let stance = take.stance(Default::default());
    let shown = [Shown {
        skeleton: &take.skeleton,
        motion: &take.motion,
        up: Default::default(),
        stance,
        mesh: None,
    }];
    let mut sequence = || {
        let start = Instant::now();
        animation::drawn_and_written(
            count,
            |frame, spare| {
                let options = SnapshotOptions {
                    frame,
                    ..SnapshotOptions::default()
                };
                renderer.render_frame(&shown, &options, &Default::default(), spare)
            },
            |pictures| {
                for (i, picture) in pictures.enumerate() {
                    let path = out.join(format!("frame_{i:05}.png"));
                    let bytes = picture?.png_fast(&path)?;
                    std::fs::write(&path, bytes).map_err(|e| bvhview::Error::io(&path, e))?;
                }
                Ok(())
            },
        )
        .expect("writes");
        start.elapsed() / count as u32
    };
    let mut article = Renderer::new(600, 600).expect("OSMesa");
    let mut display = || {
        let gl = &mut article.context().gl;
        scene::init(gl);
        let camera = Camera::default();
        let start = Instant::now();
        for frame in 0..count {
            scene::reshape(gl, 600, 600, &camera);
            let view = Scene {
                skeleton: &take.skeleton,
                frame: Some(take.motion.frame(frame)),
                camera,
                style: bvhview::render::draw::Style::Points,
                offset_mode: Default::default(),
                skin: None,
                shown: None,
                sphere_radius: 1.0,
                up: Default::default(),
                origin: [0.0; 3],
                scale: 1.0,
                colours: None,
            };
            scene::display(gl, &view);
            // SAFETY: the context is current on this thread.
            unsafe { glow::HasContext::finish(&gl.gl) };
        }
        start.elapsed() / count as u32
    };
    let (mut ours, mut theirs) = (Vec::new(), Vec::new());
    for _ in 0..rounds {
        ours.push(sequence());
        theirs.push(display());
    }
    std::fs::remove_dir_all(&out).ok();
    let (om, of) = median_and_min(&mut ours);
    let (tm, tf) = median_and_min(&mut theirs);
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!(
        "sequence of {count} frames, CMU, 600×600, {rounds} rounds in turn (per frame, median and fastest):"
    );
    println!(
        "  snapshot --frames into PNGs        median {:6.2} ms   fastest {:6.2} ms",
        ms(om),
        ms(of)
    );
    println!(
        "  the article's display() + glFinish median {:6.2} ms   fastest {:6.2} ms",
        ms(tm),
        ms(tf)
    );
    println!(
        "  snapshot / display(): {:.2} (fastest {:.2}); at most 1 is the goal",
        ms(om) / ms(tm),
        ms(of) / ms(tf)
    );
}

/// The animated outputs' encoders on the same 640×480 pictures of the CMU take (drawn once,
/// beforehand, in the article's look and the studio look): GIF, APNG and MP4 (H.264) on one
/// thread, and MP4 on every core, round-robin. Per frame, median and fastest of the rounds, and
/// how many times real time that is for a take at 30 and at 120 frames a second.
fn compare_encoders(quick: bool) {
    use bvhview::render::animation::{self, AnimationFormat};
    use bvhview::render::{Image, Look, Renderer, SnapshotOptions};
    let file =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/bvh/assimp_01_01.bvh");
    let Ok(take) = bvhview::Take::open(&file) else {
        println!("encoders: skipped (no {})", file.display());
        return;
    };
    let (rounds, count) = if quick { (3, 30) } else { (5, 120) };
    let (width, height) = (640, 480);
    let mut renderer = Renderer::new(width, height).expect("OSMesa (apt-get install libosmesa6)");
    let out = std::env::temp_dir().join(format!("bvhview-bench-encode-{}", std::process::id()));
    std::fs::create_dir_all(&out).expect("a temporary folder");
    let cores = bvhview::plumbing::cores();
    for (look_name, look) in [("article", Look::Article), ("studio", Look::Studio)] {
        let pictures: Vec<Image> = (0..count)
            .map(|frame| {
                let options = SnapshotOptions {
                    frame: frame % take.motion.frame_count(),
                    width,
                    height,
                    look,
                    ..SnapshotOptions::default()
                };
                renderer
                    .render(&take.skeleton, &take.motion, &options)
                    .expect("draws")
            })
            .collect();
        let encode = |format: AnimationFormat, threads: usize| {
            let start = Instant::now();
            match (format, threads) {
                (AnimationFormat::Mp4, threads) => {
                    let mut video =
                        bvhview::render::video::Mp4::new((width, height), 30.0, threads)
                            .expect("an encoder");
                    for picture in &pictures {
                        video.push(picture).expect("encodes");
                    }
                    std::fs::write(out.join("walk.mp4"), video.finish().expect("muxes"))
                        .expect("writes");
                }
                (format, _) => {
                    let path = out.join(if format == AnimationFormat::Gif {
                        "walk.gif"
                    } else {
                        "walk.apng"
                    });
                    let frames = pictures.iter().map(|p| Ok(p.clone()));
                    animation::write(&path, format, (width, height), 30.0, frames, count)
                        .expect("writes");
                }
            }
            start.elapsed() / count as u32
        };
        let tools = [
            ("GIF, one thread", AnimationFormat::Gif, 1),
            ("APNG, one thread", AnimationFormat::Apng, 1),
            ("MP4 (H.264), one thread", AnimationFormat::Mp4, 1),
            ("MP4 (H.264), every core", AnimationFormat::Mp4, cores),
        ];
        let mut times: Vec<Vec<Duration>> = vec![Vec::new(); tools.len()];
        for _ in 0..rounds {
            for (tool, &(_, format, threads)) in tools.iter().enumerate() {
                times[tool].push(encode(format, threads));
            }
        }
        println!(
            "encoding {count} pictures of 640×480, {look_name} look, {rounds} rounds in turn ({cores} cores; per frame, median and fastest):"
        );
        for (tool, &(name, _, _)) in tools.iter().enumerate() {
            let (median, fastest) = median_and_min(&mut times[tool]);
            let fps = 1.0 / median.as_secs_f64();
            println!(
                "  {name:<26} median {:6.2} ms   fastest {:6.2} ms   {:5.1}× real time at 30 fps, {:4.1}× at 120",
                median.as_secs_f64() * 1e3,
                fastest.as_secs_f64() * 1e3,
                fps / 30.0,
                fps / 120.0
            );
        }
    }
    std::fs::remove_dir_all(&out).ok();
}

/// The work of `bvhview info`, `positions -o FILE.csv` and `dataset DIR -o OUT` on the file at
/// `path`, in this process, timed from the call to its end: `bvhview-bench --in-process WHAT
/// PATH` prints the seconds. Run under `taskset -c 0` every call has one core and one thread
/// (the library asks the affinity mask how many cores it has).
fn in_process(what: &str, path: &str) {
    let file = std::path::Path::new(path);
    let scratch = std::env::temp_dir().join(format!("bvhview-bench-{}", std::process::id()));
    let start = Instant::now();
    match what {
        "info" => {
            // What the CLI prints: the load, then the summary (units, up axis, warnings).
            let loaded = bvhview::Take::open(file).expect("loads");
            let summary = bvhview::info::summary(
                path,
                &loaded,
                bvhview::model::pose::OffsetMode::Replace,
                &bvhview::RustSpelling,
            );
            std::hint::black_box(summary);
        }
        "positions" => {
            // Written as the CLI writes it: a temporary file, synced, renamed.
            let loaded = bvhview::Take::open(file).expect("loads");
            let frames = loaded.motion.frame_count();
            let mut out = std::io::BufWriter::with_capacity(
                1 << 20,
                bvhview::plumbing::AtomicFile::create(&scratch).expect("creates"),
            );
            bvhview::positions::write_positions(
                &mut out,
                &loaded.skeleton,
                &loaded.motion,
                0..frames,
                &Default::default(),
            )
            .expect("writes");
            let file = out
                .into_inner()
                .map_err(|e| e.into_error())
                .expect("writes");
            file.commit().expect("renames");
        }
        "dataset" => {
            let dir = file.parent().expect("a folder");
            let items = bvhview::dataset::takes(dir).expect("takes");
            let takes = bvhview::dataset::whole_list(dir, &items);
            let options = bvhview::dataset::Options::default();
            bvhview::dataset::compile(dir, items, &options, 1, &scratch, takes, |_, _, _, _| true)
                .expect("compiles");
        }
        _ => usage_error(&format!("--in-process info|positions|dataset, not {what}")),
    }
    let took = start.elapsed();
    let _ = std::fs::remove_file(&scratch);
    let _ = std::fs::remove_dir_all(&scratch);
    println!("{}", took.as_secs_f64());
}

/// One core end to end: each command of the CLI under `taskset -c 0` against the same work in
/// one process on the same core (`--in-process`), in turn in each round. `dataset` compiles the
/// folder that holds only `path` (made beside it by the caller: `DIR/big.bvh`).
fn one_core(path: &str, rounds: usize) {
    let here = std::env::current_exe().expect("the bench's own path");
    let cli = here.with_file_name("bvhview");
    if !cli.exists() {
        println!(
            "one core: skipped ({} not built: cargo build --release)",
            cli.display()
        );
        return;
    }
    let file = std::path::Path::new(path);
    let alone = file
        .parent()
        .is_some_and(|dir| std::fs::read_dir(dir).map_or(0, |d| d.count()) == 1);
    let scratch = std::env::temp_dir().join(format!("bvhview-bench-cli-{}", std::process::id()));
    let csv = scratch.with_extension("csv");
    let wall = |command: &mut std::process::Command| {
        let start = Instant::now();
        let status = command
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status()
            .expect("runs");
        let took = start.elapsed();
        assert!(status.success(), "{command:?} failed");
        took
    };
    // The work's own time as the process measures it, and the whole process's (its start and
    // exit included, as the CLI's are).
    let inside = |what: &str| {
        let start = Instant::now();
        let out = std::process::Command::new("taskset")
            .args(["-c", "0"])
            .arg(&here)
            .args(["--in-process", what, path])
            .output()
            .expect("runs");
        let whole = start.elapsed();
        let text = String::from_utf8_lossy(&out.stdout);
        (
            Duration::from_secs_f64(text.trim().parse().expect("seconds")),
            whole,
        )
    };
    let mut works = vec!["info", "positions"];
    if alone {
        works.push("dataset");
    } else {
        println!("one core: dataset skipped ({path} is not alone in its folder)");
    }
    let mut times = vec![(Vec::new(), Vec::new(), Vec::new()); works.len()];
    for _ in 0..rounds {
        for (k, what) in works.iter().enumerate() {
            let mut command = std::process::Command::new("taskset");
            command.args(["-c", "0"]).arg(&cli);
            match *what {
                "info" => command.args(["info", path]),
                "positions" => {
                    // A new file, as the in-process run writes: replacing one costs what this
                    // file system takes to free the old one's blocks, which is not the work.
                    let _ = std::fs::remove_file(&csv);
                    command.args(["positions", path, "-o"]).arg(&csv)
                }
                _ => {
                    let _ = std::fs::remove_dir_all(&scratch);
                    command
                        .args(["dataset"])
                        .arg(file.parent().expect("a folder"))
                        .arg("-o")
                        .arg(&scratch)
                }
            };
            times[k].0.push(wall(&mut command));
            let (own, whole) = inside(what);
            times[k].1.push(own);
            times[k].2.push(whole);
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    let _ = std::fs::remove_file(&csv);
    println!(
        "one core (taskset -c 0), {rounds} rounds in turn; the CLI's wall time against the same work in process:"
    );
    let pairs = |a: &[Duration], b: &[Duration]| {
        let mut ratios: Vec<f64> = a
            .iter()
            .zip(b)
            .map(|(a, b)| a.as_secs_f64() / b.as_secs_f64())
            .collect();
        ratios.sort_by(f64::total_cmp);
        (
            ratios[ratios.len() / 2],
            ratios[0],
            ratios[ratios.len() - 1],
        )
    };
    for (what, (cli, inside, whole)) in works.iter().zip(&mut times) {
        // Each round's CLI run against the in-process run just after it: the pair shares the
        // machine's state, so the ratio holds when the machine's speed drifts between rounds.
        let (own, own_low, own_high) = pairs(cli, inside);
        let (all, all_low, all_high) = pairs(cli, whole);
        let (cm, cf) = median_and_min(cli);
        let (im, imin) = median_and_min(inside);
        println!(
            "  {what:10} CLI median {:7.1} ms fastest {:7.1} ms   in process median {:7.1} ms fastest {:7.1} ms\n  \
             {:10} CLI/in process, pair by pair: median {own:.3} (from {own_low:.3} to {own_high:.3}); \
             against the in-process run's whole process (its start and exit too): median {all:.3} (from {all_low:.3} to {all_high:.3})",
            cm.as_secs_f64() * 1e3,
            cf.as_secs_f64() * 1e3,
            im.as_secs_f64() * 1e3,
            imin.as_secs_f64() * 1e3,
            ""
        );
    }
}

/// The folder a dataset of `path` is compiled from, and its takes: the file alone, or a folder
/// of takes.
fn dataset_items(path: &str) -> (std::path::PathBuf, Vec<bvhview::info::batch::Item>) {
    let path = std::path::Path::new(path);
    if path.is_dir() {
        let items = bvhview::dataset::takes(path).unwrap_or_else(|e| input_error(e));
        return (path.to_path_buf(), items);
    }
    let item = bvhview::info::batch::Item {
        path: path.to_path_buf(),
        motion: None,
    };
    (path.parent().expect("a folder").to_path_buf(), vec![item])
}

/// `dataset --onto smpl22 --features humanml3d` against `dataset --onto smpl22` (its
/// default 30 fps, and at HumanML3D's 20), in this process, in turn in each round, on one
/// thread and on every core: source frames per second.
fn humanml3d_against_onto(path: &str, rounds: usize) {
    use bvhview::dataset::{FeatureSet, Options};
    let (dir, items) = dataset_items(path);
    let target = bvhview::retarget::Target::load("smpl22", u64::MAX).expect("built in");
    let onto = Options {
        onto: Some(target),
        ..Options::default()
    };
    let kinds = [
        ("--onto smpl22 (30 fps)", onto.clone()),
        (
            "--onto smpl22 --fps 20",
            Options {
                fps: 20.0,
                ..onto.clone()
            },
        ),
        (
            "--onto smpl22 --features humanml3d",
            Options {
                fps: 20.0,
                features: FeatureSet::HumanMl3d,
                ..onto
            },
        ),
    ];
    let frames: usize = items
        .iter()
        .filter_map(|item| {
            let mut options = bvhview::take::OpenOptions::new()
                .threads(1)
                .max_size(u64::MAX);
            if let Some(amc) = &item.motion {
                options = options.motion(amc);
            }
            options.open(&item.path).ok()
        })
        .map(|take| take.motion.frame_count())
        .sum();
    let scratch = std::env::temp_dir().join(format!("bvhview-bench-h3-{}", std::process::id()));
    for threads in [1, bvhview::plumbing::cores()] {
        let mut times = vec![Vec::new(); kinds.len()];
        for _ in 0..rounds {
            for ((_, options), times) in kinds.iter().zip(&mut times) {
                let _ = std::fs::remove_dir_all(&scratch);
                let takes = bvhview::dataset::whole_list(&dir, &items);
                let start = Instant::now();
                bvhview::dataset::compile(
                    &dir,
                    items.clone(),
                    options,
                    threads,
                    &scratch,
                    takes,
                    |_, _, _, _| true,
                )
                .expect("compiles");
                times.push(start.elapsed());
            }
        }
        println!(
            "dataset onto smpl22, {threads} thread(s), {rounds} rounds in turn, source frames/s:"
        );
        for ((name, _), times) in kinds.iter().zip(&mut times) {
            let (median, fastest) = median_and_min(times);
            println!(
                "  {name:36} median {:9.0} ({:.1} ms), fastest {:9.0}",
                frames as f64 / median.as_secs_f64(),
                median.as_secs_f64() * 1e3,
                frames as f64 / fastest.as_secs_f64()
            );
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
}

/// `dataset` in this process, one thread: each stage's share of the time
/// (`dataset::compile_take_timed`, summed over the takes), writing the files included. `path` is
/// the file alone in its folder, or a folder of takes.
fn dataset_stages(path: &str, rounds: usize) {
    let (dir, items) = dataset_items(path);
    let dir = dir.as_path();
    let options = bvhview::dataset::Options::default();
    let scratch = std::env::temp_dir().join(format!("bvhview-bench-ds-{}", std::process::id()));
    let mut runs = Vec::new();
    for _ in 0..rounds {
        let start = Instant::now();
        let mut stages = bvhview::dataset::Stages::default();
        for item in &items {
            // A take the dataset skips costs what it took to find that out.
            if let Ok((clip, of_take)) = bvhview::dataset::compile_take_timed(dir, item, &options) {
                drop(clip);
                stages.add(&of_take);
            }
        }
        let summed = start.elapsed();
        // The whole compile, files written and synced: writing is what it adds to the stages.
        let _ = std::fs::remove_dir_all(&scratch);
        let takes = bvhview::dataset::whole_list(dir, &items);
        let start = Instant::now();
        bvhview::dataset::compile(
            dir,
            items.clone(),
            &options,
            1,
            &scratch,
            takes,
            |_, _, _, _| true,
        )
        .expect("compiles");
        let whole = start.elapsed();
        runs.push((stages, whole.saturating_sub(summed)));
    }
    let _ = std::fs::remove_dir_all(&scratch);
    let size: usize = items
        .iter()
        .flat_map(|item| std::iter::once(&item.path).chain(&item.motion))
        .map(|file| std::fs::metadata(file).map_or(0, |m| m.len() as usize))
        .sum();
    // The round whose stages add up to the median total.
    let total = |(s, w): &(bvhview::dataset::Stages, Duration)| {
        s.load + s.rotations + s.resample + s.fk + s.kinds + s.derived + *w
    };
    runs.sort_by_key(total);
    let (stages, writing) = runs[runs.len() / 2];
    let all = total(&(stages, writing));
    println!(
        "dataset, one thread, median of {rounds} rounds: {:.1} ms, {:.1} MB/s of input; stage shares:",
        all.as_secs_f64() * 1e3,
        mb_per_s(size, all)
    );
    for (name, time) in [
        ("load (read + parse)", stages.load),
        ("rotations (channels to quaternions)", stages.rotations),
        ("resample (interpolate, metres, Y up)", stages.resample),
        ("FK (world positions)", stages.fk),
        ("rotation kind + translations", stages.kinds),
        ("derived (path, velocities, contacts)", stages.derived),
        ("writing (npy files, sync, rename)", writing),
    ] {
        println!(
            "  {name:38} {:8.1} ms {:5.1} %",
            time.as_secs_f64() * 1e3,
            100.0 * time.as_secs_f64() / all.as_secs_f64()
        );
    }
}

/// Linear blend skinning on one core: each character's own take, every frame skinned in turn,
/// `rounds` rounds; vertex-influences a second (median and fastest round), and what a frame
/// costs beside a 120 fps take's 8.3 ms.
fn skinning(rounds: usize, extra: Option<&str>) {
    use bvhview::character::Character;
    let files = [
        "tests/data/characters/maya_kenney_character_7700_binary.fbx",
        "tests/data/characters/capsule_mixamo.fbx",
        "tests/data/characters/capsule_mixamo.glb",
    ];
    let mut cases: Vec<(String, Character)> = Vec::new();
    for file in files.into_iter().chain(extra) {
        let character = Character::open(file).unwrap_or_else(|e| input_error(e));
        cases.push((
            file.rsplit('/').next().unwrap_or(file).to_string(),
            character,
        ));
    }
    // Ten capsule men in one mesh: 29,040 vertices on one skeleton.
    let mut big = cases[1].1.clone();
    let one = big.mesh.clone();
    for _ in 1..10 {
        big.mesh.append(one.clone());
    }
    cases.push(("capsule_mixamo.fbx ×10".to_string(), big));
    println!("skinning: one core, {rounds} rounds, each round every frame of the take");
    for (name, character) in &cases {
        let take = &character.take;
        let mesh = &character.mesh;
        let influences = mesh.influences.len();
        let mut world = Vec::new();
        let mut bones = Vec::new();
        let (mut positions, mut normals) = (Vec::new(), Vec::new());
        let mut times = Vec::with_capacity(rounds);
        let mut checksum = 0.0f32;
        for _ in 0..rounds {
            let start = Instant::now();
            for f in 0..take.frame_count() {
                bvhview::model::pose::world_matrices(
                    &take.skeleton,
                    take.motion.frame(f),
                    bvhview::model::pose::OffsetMode::Replace,
                    &mut world,
                );
                mesh.bone_matrices(&world, &mut bones);
                mesh.deform_with(&bones, &mut positions, &mut normals);
                checksum += positions[f % positions.len()].y;
            }
            times.push(start.elapsed() / take.frame_count() as u32);
        }
        times.sort();
        let (median, fastest) = (times[times.len() / 2], times[0]);
        let rate = |t: Duration| influences as f64 / t.as_secs_f64() / 1e6;
        println!(
            "  {name}: {} vertices, {influences} influences ({:.2} a vertex): {:.3} ms a frame \
             median ({:.3} fastest) = {:.1} M vertex-influences/s median ({:.1} fastest) \
             [checksum {checksum:.3}]",
            mesh.vertex_count(),
            influences as f64 / mesh.vertex_count() as f64,
            median.as_secs_f64() * 1e3,
            fastest.as_secs_f64() * 1e3,
            rate(median),
            rate(fastest),
        );
    }
    // What the window does a frame: the CMU walk (120 fps, 8.3 ms a frame) on each character,
    // posed, skinned and drawn in the studio look at 600×600 by OSMesa's llvmpipe (the software
    // GL the window gets under Xvfb), the picture read back as well.
    let walk_path = "tests/data/bvh/bvh11_131_01.bvh";
    let walk = bvhview::Take::open(walk_path)
        .unwrap_or_else(|e| input_error(e))
        .trim(0..120);
    let Ok(mut renderer) = bvhview::render::Renderer::new(600, 600) else {
        println!("  drawing: skipped (no OSMesa)");
        return;
    };
    for (name, character) in &cases {
        let (dressed, _) = character
            .dress(&walk, &[], Default::default(), 1)
            .unwrap_or_else(|e| input_error(e));
        let shown = [bvhview::render::paint::Shown {
            skeleton: &dressed.skeleton,
            motion: &dressed.motion,
            up: Default::default(),
            stance: dressed.stance(Default::default()),
            mesh: Some(&character.mesh),
        }];
        let mut times = Vec::new();
        for _ in 0..rounds.min(3) {
            let start = Instant::now();
            for frame in 0..dressed.frame_count() {
                let options = bvhview::render::SnapshotOptions {
                    frame,
                    look: bvhview::render::Look::Studio,
                    style: bvhview::render::draw::Style::Points,
                    ..Default::default()
                };
                renderer
                    .render_all(&shown, &options, &Default::default())
                    .expect("drawn");
            }
            times.push(start.elapsed() / dressed.frame_count() as u32);
        }
        times.sort();
        println!(
            "  drawn: the CMU walk on {name}, studio look 600x600 (OSMesa): {:.2} ms a frame \
             median ({:.2} fastest); the take's 120 fps leave 8.33 ms",
            times[times.len() / 2].as_secs_f64() * 1e3,
            times[0].as_secs_f64() * 1e3
        );
    }
}
