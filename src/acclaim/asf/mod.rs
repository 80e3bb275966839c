//! The ASF skeleton file: `:units`, `:root`, `:bonedata` (begin … end per bone: id, name,
//! direction, length, axis, dof, limits) and `:hierarchy` (begin, one `parent child…` line per
//! parent, end). The ASF/AMC article's `Read_ASF`; unlike it, any number of bones and frames,
//! keywords in any case, and an error with the line and column for anything malformed.

use super::text::{Word, error_at, expected, expected_after, expected_at_start, lines, number};
use crate::io::error::Error;
use crate::limits::MAX_DEPTH;
use std::path::Path;

mod bones;
mod parsed;

pub use bones::ValueMap;
use bones::bone_vector;
pub use parsed::{Asf, Bone, Dof, Root, Units};

/// Reads an ASF file; reading stops with an error past `max_size` bytes.
pub fn load_asf(path: &Path, max_size: u64) -> Result<Asf, Error> {
    let bytes = crate::io::read::read_skeleton_file(path, max_size)?;
    parse_asf(
        &String::from_utf8_lossy(&bytes),
        &path.display().to_string(),
    )
}

fn axis_order(source: &str, word: &Word<'_>) -> Result<[usize; 3], Error> {
    let letters: Vec<usize> = word
        .text
        .chars()
        .filter_map(|c| match c.to_ascii_uppercase() {
            'X' => Some(0),
            'Y' => Some(1),
            'Z' => Some(2),
            _ => None,
        })
        .collect();
    match letters[..] {
        [a, b, c] if word.text.len() == 3 && a != b && b != c && a != c => Ok([a, b, c]),
        _ => Err(expected(source, word, "a rotation order such as XYZ")),
    }
}

fn three(source: &str, line: &[Word<'_>], what: &str) -> Result<[f64; 3], Error> {
    if line.len() < 4 {
        return Err(expected_after(
            source,
            line,
            &format!("three numbers ({what})"),
        ));
    }
    let mut out = [0.0; 3];
    for (value, word) in out.iter_mut().zip(&line[1..4]) {
        *value = number(source, word, &format!("a number ({what})"))?;
    }
    Ok(out)
}

/// A limit bound: a number or `inf` / `-inf`, possibly with the parentheses attached.
fn bound(source: &str, word: &Word<'_>) -> Result<f64, Error> {
    let text = word.text.trim_matches(|c| c == '(' || c == ')');
    match text.to_ascii_lowercase().as_str() {
        "inf" | "+inf" => Ok(f64::INFINITY),
        "-inf" => Ok(f64::NEG_INFINITY),
        _ => text
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| expected(source, word, "a limit (a number or inf)")),
    }
}

/// Which section of an ASF file a line is in.
#[derive(PartialEq)]
enum Section {
    None,
    Units,
    Root,
    BoneData,
    Hierarchy,
    Other,
}

/// The bones of `:bonedata` as they are read.
#[derive(Default)]
struct BoneData {
    bones: Vec<Bone>,
    /// Bone names to indices: files with many bones must not cost a search per name.
    names: std::collections::HashMap<String, usize>,
    /// The bone between `begin` and `end`.
    current: Option<Bone>,
    /// `(min max)` lines still expected for the current bone's dofs.
    pending_limits: usize,
}

/// Parses ASF text; `source` names it in errors. One function per section reads its lines;
/// then the tree is built from `:hierarchy`.
pub fn parse_asf(text: &str, source: &str) -> Result<Asf, Error> {
    let all = lines(text);
    let mut reading = Reading::new();
    for line in &all {
        reading.line(source, line)?;
    }
    let end_line = all.last().map_or(1, |l| l[0].line + 1);
    reading.finish(source, end_line)
}

/// An ASF file as its lines are read: what each section has said so far.
struct Reading<'a> {
    units: Units,
    root: Option<Root>,
    data: BoneData,
    /// Each hierarchy line: the parent's name, then its children's.
    hierarchy: Vec<Vec<Word<'a>>>,
    seen_hierarchy: bool,
    seen_bonedata: bool,
    section: Section,
}

impl<'a> Reading<'a> {
    fn new() -> Reading<'a> {
        Reading {
            units: Units {
                mass: 1.0,
                length: 1.0,
                degrees: true,
            },
            root: None,
            data: BoneData::default(),
            hierarchy: Vec::new(),
            seen_hierarchy: false,
            seen_bonedata: false,
            section: Section::None,
        }
    }

    /// One line: a section's name opens it, any other line belongs to the open section.
    fn line(&mut self, source: &str, line: &[Word<'a>]) -> Result<(), Error> {
        let first = &line[0];
        if first.text.starts_with(':') {
            return self.open(source, first);
        }
        match self.section {
            Section::None => {
                return Err(expected_at_start(
                    source,
                    first,
                    "a section such as :root",
                    &[
                        ":version",
                        ":name",
                        ":units",
                        ":documentation",
                        ":root",
                        ":bonedata",
                        ":hierarchy",
                    ],
                ));
            }
            Section::Other => {}
            Section::Units => units_line(source, line, &mut self.units)?,
            Section::Root => root_line(
                source,
                line,
                self.root.as_mut().expect(":root opened the section"),
            )?,
            Section::BoneData => self.data.line(source, line)?,
            Section::Hierarchy => hierarchy_line(source, line, &mut self.hierarchy)?,
        }
        Ok(())
    }

    /// A section's name (`:root`, …): the section it opens, once the bone before is closed.
    fn open(&mut self, source: &str, first: &Word<'_>) -> Result<(), Error> {
        if let Some(bone) = &self.data.current {
            return Err(expected(
                source,
                first,
                &format!("'end' to close bone '{}'", bone.name),
            ));
        }
        self.section = match first.text.to_ascii_lowercase().as_str() {
            ":units" => Section::Units,
            ":root" => {
                self.root = Some(Root {
                    order: Vec::new(),
                    axis_order: [0, 1, 2],
                    position: [0.0; 3],
                    orientation: [0.0; 3],
                });
                Section::Root
            }
            ":bonedata" => {
                self.seen_bonedata = true;
                Section::BoneData
            }
            ":hierarchy" => {
                self.seen_hierarchy = true;
                Section::Hierarchy
            }
            _ => Section::Other,
        };
        self.data.pending_limits = 0;
        Ok(())
    }

    /// The file read to its end (`end_line` is past its last line): refuses a bone left open or
    /// a section missing, then the angles in degrees, the directions unit vectors, the tree.
    fn finish(self, source: &str, end_line: usize) -> Result<Asf, Error> {
        let Reading {
            units,
            root,
            data,
            hierarchy,
            seen_hierarchy,
            seen_bonedata,
            ..
        } = self;
        let BoneData {
            mut bones,
            names,
            current,
            ..
        } = data;
        if let Some(bone) = &current {
            return Err(error_at(
                source,
                end_line,
                1,
                format!(
                    "expected 'end' to close bone '{}', found end of file",
                    bone.name
                ),
            ));
        }
        let Some(mut root) = root else {
            return Err(error_at(
                source,
                end_line,
                1,
                "missing section :root".into(),
            ));
        };
        if !seen_bonedata {
            return Err(error_at(
                source,
                end_line,
                1,
                "missing section :bonedata".into(),
            ));
        }
        if !seen_hierarchy {
            return Err(error_at(
                source,
                end_line,
                1,
                "missing section :hierarchy".into(),
            ));
        }
        if root.order.is_empty() {
            root.order = vec![Dof::Tx, Dof::Ty, Dof::Tz, Dof::Rx, Dof::Ry, Dof::Rz];
        }

        if !units.degrees {
            to_degrees(&mut root, &mut bones);
        }
        let mut warnings: Vec<String> = normalise_directions(&mut bones).into_iter().collect();
        check_bone_vectors(source, &bones)?;
        let (root_children, children, tree_warnings) =
            build_tree(source, &bones, &names, &hierarchy)?;
        warnings.extend(tree_warnings);
        Ok(Asf {
            units,
            root,
            bones,
            root_children,
            children,
            warnings,
        })
    }
}

/// Refuses a bone whose `direction × length` is past a 32-bit float: each number fits one;
/// their product must too.
fn check_bone_vectors(source: &str, bones: &[Bone]) -> Result<(), Error> {
    for bone in bones {
        if !bone_vector(bone).is_finite() {
            return Err(error_at(
                source,
                bone.line,
                1,
                format!(
                    "bone '{}': direction × length is too large for a 32-bit float",
                    bone.name
                ),
            ));
        }
    }
    Ok(())
}

/// How far a direction's length may be from 1 and still be taken as written: files print six
/// digits or so, and rescaling those would move every position by rounding noise.
const UNIT_TOLERANCE: f64 = 1e-3;

/// Makes every bone's direction a unit vector, as Acclaim defines it (the bone's length is its
/// `length`), and says so once: a file with scaled directions draws blown up otherwise.
fn normalise_directions(bones: &mut [Bone]) -> Option<String> {
    let mut changed: Vec<(&str, usize, f64)> = Vec::new();
    for bone in bones.iter_mut() {
        // Scaled by the largest component first, so that tiny or huge components neither
        // underflow nor overflow on the way to the length.
        let largest = bone.direction.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
        let scaled = bone.direction.map(|d| d / largest);
        let length_of_scaled = scaled.iter().map(|d| d * d).sum::<f64>().sqrt();
        let length = largest * length_of_scaled;
        if (length - 1.0).abs() > UNIT_TOLERANCE {
            bone.direction = scaled.map(|d| d / length_of_scaled);
            changed.push((&bone.name, bone.line, length));
        }
    }
    let (name, line, length) = *changed.first()?;
    let length = length as f32;
    Some(match changed.len() {
        1 => format!(
            "bone '{name}' (line {line}): direction is {length} long, not a unit vector: \
             normalised (the bone's length is its 'length')"
        ),
        n => format!(
            "{n} bones' directions are not unit vectors (the first, '{name}' at line {line}, is \
             {length} long): normalised (each bone's length is its 'length')"
        ),
    })
}

/// A line of `:units`.
fn units_line(source: &str, line: &[Word<'_>], units: &mut Units) -> Result<(), Error> {
    let first = &line[0];
    let value = line
        .get(1)
        .ok_or_else(|| expected_after(source, line, "a value"))?;
    if first.is("mass") {
        units.mass = number(source, value, "a number")?;
    } else if first.is("length") {
        units.length = number(source, value, "a number")?;
    } else if first.is("angle") {
        units.degrees = if value.is("deg") || value.is("degrees") {
            true
        } else if value.is("rad") || value.is("radians") {
            false
        } else {
            return Err(expected(source, value, "deg or rad"));
        };
    }
    Ok(())
}

/// A line of `:root`.
fn root_line(source: &str, line: &[Word<'_>], root: &mut Root) -> Result<(), Error> {
    let first = &line[0];
    if first.is("order") {
        root.order.clear();
        for word in &line[1..] {
            let dof = Dof::parse(word.text)
                .ok_or_else(|| expected(source, word, "TX, TY, TZ, RX, RY or RZ"))?;
            if root.order.contains(&dof) {
                return Err(error_at(
                    source,
                    word.line,
                    word.column,
                    format!("'{}' listed twice", word.text),
                ));
            }
            root.order.push(dof);
        }
    } else if first.is("axis") {
        let word = line
            .get(1)
            .ok_or_else(|| expected_after(source, line, "a rotation order"))?;
        root.axis_order = axis_order(source, word)?;
    } else if first.is("position") {
        root.position = three(source, line, "root position")?;
    } else if first.is("orientation") {
        root.orientation = three(source, line, "root orientation")?;
    } else {
        return Err(expected(
            source,
            first,
            "order, axis, position or orientation",
        ));
    }
    Ok(())
}

impl BoneData {
    /// A line of `:bonedata`: `begin`, a field of the current bone, or `end`.
    fn line(&mut self, source: &str, line: &[Word<'_>]) -> Result<(), Error> {
        let first = &line[0];
        if first.is("begin") {
            return self.begin(source, first);
        }
        let Some(bone) = self.current.as_mut() else {
            return Err(expected(source, first, "'begin'"));
        };
        if first.is("end") {
            self.end(source, first)
        } else {
            bone_field(source, line, bone, &mut self.pending_limits)
        }
    }

    /// `begin`: a new bone, with neither name, direction nor length yet.
    fn begin(&mut self, source: &str, first: &Word<'_>) -> Result<(), Error> {
        if self.current.is_some() {
            return Err(expected(source, first, "'end' before the next 'begin'"));
        }
        self.current = Some(Bone {
            id: None,
            name: String::new(),
            direction: [f64::NAN; 3],
            length: f64::NAN,
            axis: [0.0; 3],
            axis_order: [0, 1, 2],
            dof: Vec::new(),
            limits: Vec::new(),
            line: first.line,
        });
        self.pending_limits = 0;
        Ok(())
    }

    /// `end`: the current bone is complete, under a name no bone before it has.
    fn end(&mut self, source: &str, first: &Word<'_>) -> Result<(), Error> {
        let bone = self.current.take().expect("checked above");
        let what = if bone.name.is_empty() {
            Some("a name")
        } else if bone.direction[0].is_nan() {
            Some("a direction")
        } else if bone.length.is_nan() {
            Some("a length")
        } else {
            None
        };
        if let Some(what) = what {
            let name = if bone.name.is_empty() {
                "bone"
            } else {
                bone.name.as_str()
            };
            return Err(error_at(
                source,
                first.line,
                first.column,
                format!("'{name}' (begun at line {}) ends without {what}", bone.line),
            ));
        }
        if self.names.contains_key(&bone.name) {
            return Err(error_at(
                source,
                bone.line,
                1,
                format!("a second bone named '{}'", bone.name),
            ));
        }
        self.names.insert(bone.name.clone(), self.bones.len());
        self.bones.push(bone);
        Ok(())
    }
}

/// A field of the bone between `begin` and `end`: id, name, direction, length, axis, dof or
/// limits (`pending_limits` counts the limits its dofs still expect).
fn bone_field(
    source: &str,
    line: &[Word<'_>],
    bone: &mut Bone,
    pending_limits: &mut usize,
) -> Result<(), Error> {
    let first = &line[0];
    if first.is("id") {
        let word = line
            .get(1)
            .ok_or_else(|| expected_after(source, line, "an id"))?;
        bone.id = Some(
            word.text
                .parse()
                .map_err(|_| expected(source, word, "an integer id"))?,
        );
    } else if first.is("name") {
        let word = line
            .get(1)
            .ok_or_else(|| expected_after(source, line, "a name"))?;
        if word.is("root") {
            return Err(expected(source, word, "a bone name other than 'root'"));
        }
        crate::limits::name(word.text.len())
            .map_err(|why| error_at(source, word.line, word.column, why))?;
        bone.name = word.text.to_string();
    } else if first.is("direction") {
        let direction = three(source, line, "direction")?;
        if direction.iter().all(|&d| d == 0.0) {
            return Err(error_at(
                source,
                line[1].line,
                line[1].column,
                format!(
                    "expected a direction along the bone (a unit vector), found '{} {} {}'",
                    line[1].text, line[2].text, line[3].text
                ),
            ));
        }
        bone.direction = direction;
    } else if first.is("length") {
        let word = line
            .get(1)
            .ok_or_else(|| expected_after(source, line, "a length"))?;
        bone.length = number(source, word, "a number (length)")?;
    } else if first.is("axis") {
        bone.axis = three(source, line, "axis")?;
        let word = line
            .get(4)
            .ok_or_else(|| expected_after(source, line, "a rotation order such as XYZ"))?;
        bone.axis_order = axis_order(source, word)?;
    } else if first.is("dof") {
        dof_line(source, line, bone)?;
        *pending_limits = bone.dof.len();
    } else if first.is("limits") || first.text.starts_with('(') {
        limits_line(source, line, bone, pending_limits)?;
    } else if first.is("bodymass") || first.is("cofmass") {
        // Known extras some exporters write; they do not change the skeleton.
    } else {
        return Err(expected(
            source,
            first,
            "id, name, direction, length, axis, dof, limits or end",
        ));
    }
    Ok(())
}

/// `dof rx ry rz`: the bone's rotations, each once (a bone neither translates nor stretches).
fn dof_line(source: &str, line: &[Word<'_>], bone: &mut Bone) -> Result<(), Error> {
    bone.dof.clear();
    for word in &line[1..] {
        let dof = if word.is("l") {
            return Err(error_at(
                source,
                word.line,
                word.column,
                "dof 'l' (a bone that stretches) is not supported".into(),
            ));
        } else {
            Dof::parse(word.text).ok_or_else(|| expected(source, word, "rx, ry or rz"))?
        };
        if !dof.is_rotation() {
            return Err(error_at(
                source,
                word.line,
                word.column,
                format!(
                    "dof '{}' on a bone is not supported: only the root translates",
                    word.text
                ),
            ));
        }
        if bone.dof.contains(&dof) {
            return Err(error_at(
                source,
                word.line,
                word.column,
                format!("dof '{}' listed twice", word.text),
            ));
        }
        bone.dof.push(dof);
    }
    Ok(())
}

/// `limits (a b)`, then one `(a b)` line per further dof; parentheses may be written apart
/// from the numbers.
fn limits_line(
    source: &str,
    line: &[Word<'_>],
    bone: &mut Bone,
    pending_limits: &mut usize,
) -> Result<(), Error> {
    let first = &line[0];
    let words: Vec<&Word<'_>> = line
        .iter()
        .skip(usize::from(first.is("limits")))
        .filter(|w| !w.text.chars().all(|c| c == '(' || c == ')'))
        .collect();
    if words.len() != 2 || *pending_limits == 0 {
        let what = if *pending_limits == 0 {
            "no more limits than dofs"
        } else {
            "(min max)"
        };
        return Err(expected(source, first, what));
    }
    bone.limits
        .push((bound(source, words[0])?, bound(source, words[1])?));
    *pending_limits -= 1;
    Ok(())
}

/// A line of `:hierarchy`: a parent and its children (`begin` and `end` pass).
fn hierarchy_line<'a>(
    source: &str,
    line: &[Word<'a>],
    hierarchy: &mut Vec<Vec<Word<'a>>>,
) -> Result<(), Error> {
    let first = &line[0];
    if first.is("begin") || first.is("end") {
        return Ok(());
    }
    if line.len() < 2 {
        return Err(expected_after(source, line, "the children of this bone"));
    }
    hierarchy.push(line.to_vec());
    Ok(())
}

/// Angles in radians become degrees, as the Skeleton's channels are.
fn to_degrees(root: &mut Root, bones: &mut [Bone]) {
    let degrees = |v: f64| v.to_degrees();
    root.orientation = root.orientation.map(degrees);
    for bone in bones {
        bone.axis = bone.axis.map(degrees);
        for (dof, limit) in bone.dof.iter().zip(bone.limits.iter_mut()) {
            if dof.is_rotation() {
                *limit = (limit.0.to_degrees(), limit.1.to_degrees());
            }
        }
    }
}

/// The tree of `:hierarchy`: the root's children, each bone's children, and a warning for each
/// bone the hierarchy leaves out. Every bone gets one parent; a loop, a second parent or nesting
/// deeper than the BVH loader allows is an error.
#[allow(clippy::type_complexity)]
fn build_tree(
    source: &str,
    bones: &[Bone],
    names: &std::collections::HashMap<String, usize>,
    hierarchy: &[Vec<Word<'_>>],
) -> Result<(Vec<usize>, Vec<Vec<usize>>, Vec<String>), Error> {
    // The tree: every bone gets one parent, and every bone must be reachable from the root.
    let index_of = |word: &Word<'_>| names.get(word.text).copied();
    let mut root_children = Vec::new();
    let mut children = vec![Vec::new(); bones.len()];
    let mut parent_of: Vec<Option<usize>> = vec![None; bones.len()];
    let mut under_root = vec![false; bones.len()];
    for line in hierarchy {
        let parent = if line[0].is("root") {
            None
        } else {
            Some(
                index_of(&line[0])
                    .ok_or_else(|| expected(source, &line[0], "a bone named in :bonedata"))?,
            )
        };
        for word in &line[1..] {
            let child = index_of(word)
                .ok_or_else(|| expected(source, word, "a bone named in :bonedata"))?;
            if parent_of[child].is_some() || under_root[child] || parent == Some(child) {
                return Err(error_at(
                    source,
                    word.line,
                    word.column,
                    format!(
                        "'{}' already has a parent: the hierarchy is not a tree",
                        word.text
                    ),
                ));
            }
            match parent {
                None => {
                    under_root[child] = true;
                    root_children.push(child);
                }
                Some(p) => {
                    parent_of[child] = Some(p);
                    children[p].push(child);
                }
            }
        }
    }
    // Reachable from the root; a bone with a parent that is not reachable sits on a loop. As in
    // the BVH loader, nesting deeper than MAX_DEPTH is refused: everything after recurses.
    let mut reached = vec![false; bones.len()];
    let mut stack: Vec<(usize, usize)> = root_children.iter().map(|&b| (b, 1)).collect();
    while let Some((bone, depth)) = stack.pop() {
        reached[bone] = true;
        if depth > MAX_DEPTH {
            let word = hierarchy
                .iter()
                .flat_map(|l| l[1..].iter())
                .find(|w| w.text == bones[bone].name)
                .expect("a reached bone is named in the hierarchy");
            return Err(error_at(
                source,
                word.line,
                word.column,
                format!("bones nest deeper than {MAX_DEPTH} levels"),
            ));
        }
        stack.extend(children[bone].iter().map(|&c| (c, depth + 1)));
    }
    let mut warnings = Vec::new();
    for (i, bone) in bones.iter().enumerate() {
        if reached[i] {
            continue;
        }
        if parent_of[i].is_some() {
            let line = hierarchy
                .iter()
                .flat_map(|l| l[1..].iter())
                .find(|w| w.text == bone.name)
                .expect("a bone with a parent is named in the hierarchy");
            return Err(error_at(
                source,
                line.line,
                line.column,
                format!(
                    "the hierarchy loops through '{}' and never reaches root",
                    bone.name
                ),
            ));
        }
        warnings.push(format!(
            "bone '{}' (line {}) is not in the hierarchy and is left out",
            bone.name, bone.line
        ));
    }
    Ok((root_children, children, warnings))
}
