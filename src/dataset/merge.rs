//! Datasets merged: pieces of one compile (a Dask or Ray run) into the dataset one compile would
//! have written, byte for byte, or datasets of any folders joined by topology. Each piece is read
//! through the checked reader ([`super::read`]) and written by the dataset writer
//! ([`super::store::Writer`]).

use super::clip::Clip;
use super::folder::open_manifest;
pub use super::join::Join;
use super::options::FeatureSet;
use super::read::open;
use super::store::{Manifest, Takes, Writer, list_digest};
use super::summary::Summary;
use crate::io::error::Error;
use std::path::{Path, PathBuf};

fn floats(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// Merges datasets into `out`. With [`Join::Pieces`], they are pieces of one compile
/// (consecutive runs of one folder's takes in path order); with [`Join::Folders`], any datasets
/// made with the same options.
pub fn merge(pieces: &[PathBuf], out: &Path, join: Join) -> Result<Summary, Error> {
    let Some(first) = pieces.first() else {
        return Err(Error::usage("nothing to merge: no datasets given"));
    };
    let (_, manifest) = open_manifest(first)?;
    if manifest.options.features == FeatureSet::HumanMl3d.name() {
        return super::humanml3d::merge(pieces, out, join, |manifests| {
            takes_of(pieces, manifests, join)
        });
    }
    let datasets = pieces
        .iter()
        .map(|p| open(p))
        .collect::<Result<Vec<_>, Error>>()?;
    let manifests: Vec<&Manifest> = datasets.iter().map(|d| &d.manifest).collect();
    let takes = takes_of(pieces, &manifests, join)?;
    let first = &datasets[0];
    let options = first.manifest.options.options()?;
    // Checked when the pieces were compiled (their `onto` is a name here, not a skeleton).
    let mut writer = Writer::create_unchecked(out, &options, takes)?;
    writer.keep_settings(first.manifest.options.clone());
    for (piece, dataset) in pieces.iter().zip(datasets) {
        let manifest = &dataset.manifest;
        let skeletons = (0..manifest.groups.len())
            .map(|k| dataset.skeleton_text(k))
            .collect::<Result<Vec<_>, Error>>()?;
        let mut clip_in_group = vec![0usize; manifest.groups.len()];
        for entry in &manifest.clips {
            let group = &manifest.groups[entry.group];
            let files = &dataset.groups[entry.group];
            let rows = entry.start..entry.start + entry.frames;
            let array = |k: usize| files.arrays[k].read_rows(rows.clone());
            let index = clip_in_group[entry.group];
            clip_in_group[entry.group] += 1;
            let rest = files.arrays[7].read_rows(index..index + 1)?;
            let clip = Clip {
                about: entry.about.clone(),
                topology: group.topology.clone(),
                frames: entry.frames,
                rest_offsets: floats(&rest),
                positions: floats(&array(0)?),
                rotations: floats(&array(1)?),
                translations: floats(&array(2)?),
                root_translations: floats(&array(3)?),
                velocities: floats(&array(4)?),
                contacts: array(5)?,
                skeleton: None,
                humanml3d: None,
            };
            writer
                .add_merged(&clip, &skeletons[entry.group], String::new())
                .map_err(|e| e.about(&piece.display().to_string()))?;
        }
        for skipped in &manifest.skipped {
            writer.skip(skipped.clone());
        }
    }
    writer.finish()
}

/// The list of takes the merged datasets hold: the whole list their pieces are of, or for
/// folders, one list of them all. Their options must be one.
fn takes_of(pieces: &[PathBuf], manifests: &[&Manifest], join: Join) -> Result<Takes, Error> {
    let first = manifests[0];
    for (piece, manifest) in pieces.iter().zip(manifests) {
        if manifest.options != first.options {
            return Err(Error::usage(format!(
                "{}: made with other options than {}; datasets are merged only when they share them",
                piece.display(),
                pieces[0].display()
            )));
        }
    }
    match join {
        Join::Pieces => pieces_in_order(pieces, manifests),
        Join::Folders => {
            let digests: Vec<super::Source> = manifests
                .iter()
                .map(|m| super::Source {
                    path: m.takes.list.clone(),
                    motion: None,
                })
                .collect();
            let count = manifests.iter().map(|m| m.takes.count).sum();
            Ok(Takes {
                list: list_digest(&digests),
                listed: count,
                first: 0,
                count,
            })
        }
    }
}

/// Pieces of one compile, checked: one list of takes, its runs given in order, each take once,
/// none missing. Their paths must come in path order too (a manifest edited by hand would
/// otherwise merge into a dataset no compile makes).
fn pieces_in_order(pieces: &[PathBuf], manifests: &[&Manifest]) -> Result<Takes, Error> {
    let first = &manifests[0].takes;
    let mut next = 0usize;
    for (piece, manifest) in pieces.iter().zip(manifests) {
        let takes = &manifest.takes;
        if takes.list != first.list || takes.listed != first.listed {
            return Err(Error::usage(format!(
                "{}: a piece of another compile than {} (another folder or list of takes);                  to join datasets of different folders, merge them with join=\"folders\"",
                piece.display(),
                pieces[0].display()
            )));
        }
        if takes.first != next {
            let why = match takes.first > next {
                true => format!("takes {next} to {} are in no piece given", takes.first),
                false => format!(
                    "it starts at take {}, which an earlier piece holds",
                    takes.first
                ),
            };
            return Err(Error::usage(format!(
                "{}: {why}; pieces must be consecutive runs of list_takes, given in order,                  each take in one piece",
                piece.display()
            )));
        }
        next += takes.count;
        let held = manifest.clips.len() + manifest.skipped.len();
        if held != takes.count {
            return Err(Error::usage(format!(
                "{}: its manifest lists {held} takes where it says it holds {}",
                piece.display(),
                takes.count
            )));
        }
    }
    if next != first.listed {
        return Err(Error::usage(format!(
            "the pieces hold takes 0 to {next} of {}; the rest of the list is missing",
            first.listed
        )));
    }
    let mut last: Option<(String, &Path)> = None;
    for (piece, manifest) in pieces.iter().zip(manifests) {
        let mut paths: Vec<String> = manifest
            .clips
            .iter()
            .map(|c| &c.about.source)
            .chain(manifest.skipped.iter().map(|s| &s.source))
            .map(|s| s.motion.clone().unwrap_or_else(|| s.path.clone()))
            .collect();
        // Path order, as `takes` lists them (by component: `a/b` before `a-b`).
        paths.sort_by(|a, b| Path::new(a).cmp(Path::new(b)));
        for path in paths {
            if let Some((before, where_before)) = &last
                && Path::new(before) >= Path::new(&path)
            {
                return Err(Error::usage(format!(
                    "{}: {path} comes after {before} in {}; pieces must be consecutive runs of \
                     list_takes, given in order, each take in one piece",
                    piece.display(),
                    where_before.display()
                )));
            }
            last = Some((path, piece));
        }
    }
    Ok(Takes {
        list: first.list.clone(),
        listed: first.listed,
        first: 0,
        count: first.listed,
    })
}
