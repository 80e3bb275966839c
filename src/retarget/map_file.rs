//! Map files: the TOML or JSON `--map` reads (and `--show-map` prints), and `SRC=DST` pairs.

use crate::io::error::Error;
use crate::io::error::quoted;
use crate::model::skeleton::Skeleton;

/// Pairs over a guessed map (`SRC = DST`, an empty DST leaving a source joint out): those for
/// every skeleton, and those for one skeleton only, keyed by its
/// [`fingerprint`](crate::Skeleton::fingerprint), so that one map file serves a folder of
/// mixed rigs.
///
/// ```
/// use bvhview::retarget::{MapPairs, parse_map_pairs};
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let walk = bvhview::Take::open("tests/data/bvh/bvhparser_walk_01.bvh")?;
/// let text = format!(
///     "\"LeftToeBase\" = \"\"\n[skeleton.{}]\n\"RightToeBase\" = \"\"\n[skeleton.000000000000]\n\"x\" = \"y\"\n",
///     walk.skeleton.fingerprint()
/// );
/// let pairs: MapPairs = parse_map_pairs(&text, "map.toml")?;
/// let for_walk = pairs.for_skeleton(&walk.skeleton);
/// let sources: Vec<&str> = for_walk.iter().map(|(s, _)| s.as_str()).collect();
/// assert_eq!(sources, ["LeftToeBase", "RightToeBase"]);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MapPairs {
    /// Pairs for every skeleton, in order (later ones win).
    pub all: Vec<(String, String)>,
    /// Pairs for one skeleton, by fingerprint, after `all`.
    pub by_skeleton: Vec<(String, Vec<(String, String)>)>,
    /// What one skeleton's takes are, by fingerprint (a map file's `[stated.<fingerprint>]`:
    /// `units = "cm"`, `up = "z"`), for folders of mixed rigs.
    #[serde(skip)]
    pub stated: Vec<(String, Stated)>,
}

/// A skeleton's units and up axis, as a map file states them.
///
/// ```
/// use bvhview::retarget::parse_map_pairs;
///
/// # fn main() -> Result<(), bvhview::Error> {
/// let map = parse_map_pairs("[stated.c57cd18da1dc]\nunits = \"cm\"\nup = \"z\"\n", "rigs.toml")?;
/// let (fingerprint, stated) = &map.stated[0];
/// assert_eq!(fingerprint, "c57cd18da1dc");
/// assert_eq!(stated.units.unwrap().name, "centimetres");
/// assert_eq!(stated.up, Some(bvhview::model::pose::UpAxis::Z));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stated {
    /// The units its lengths are in.
    pub units: Option<crate::model::stance::Units>,
    /// The axis it stands along.
    pub up: Option<crate::model::pose::UpAxis>,
}

impl MapPairs {
    /// Pairs for every skeleton only.
    pub fn from_pairs(all: Vec<(String, String)>) -> MapPairs {
        MapPairs {
            all,
            ..MapPairs::default()
        }
    }

    /// Whether there is no pair at all.
    pub fn is_empty(&self) -> bool {
        self.all.is_empty() && self.by_skeleton.iter().all(|(_, pairs)| pairs.is_empty())
    }

    /// Adds `other`'s pairs after these.
    pub fn extend(&mut self, other: MapPairs) {
        self.all.extend(other.all);
        self.by_skeleton.extend(other.by_skeleton);
        self.stated.extend(other.stated);
    }

    /// What the map states of `skeleton`'s takes (its fingerprint's `[stated.…]`; the last
    /// one given wins), if anything.
    pub fn stated_for(&self, skeleton: &Skeleton) -> Stated {
        let fingerprint = skeleton.fingerprint();
        let mut stated = Stated::default();
        for (key, own) in &self.stated {
            if *key == fingerprint {
                stated.units = own.units.or(stated.units);
                stated.up = own.up.or(stated.up);
            }
        }
        stated
    }

    /// The pairs that apply to `skeleton`: those for every skeleton, then those under its
    /// fingerprint.
    pub fn for_skeleton(&self, skeleton: &Skeleton) -> Vec<(String, String)> {
        let fingerprint = skeleton.fingerprint();
        let mut pairs = self.all.clone();
        for (key, own) in &self.by_skeleton {
            if *key == fingerprint {
                pairs.extend(own.iter().cloned());
            }
        }
        pairs
    }
}

/// Reads a map file of pairs for every skeleton only (see [`parse_map_pairs`]); a file with
/// `[skeleton.…]` sections is refused here.
pub fn parse_map(text: &str, name: &str) -> Result<Vec<(String, String)>, Error> {
    let pairs = parse_map_pairs(text, name)?;
    if !pairs.by_skeleton.is_empty() || !pairs.stated.is_empty() {
        return Err(Error::usage(format!(
            "{name}: pairs for one skeleton ([skeleton.…]) are read where a take's skeleton is known"
        )));
    }
    Ok(pairs.all)
}

/// Reads a map file: JSON (`{"source": "target", …}`) or TOML (`"source" = "target"` lines,
/// what `--show-map` prints), with pairs for one skeleton under `skeleton.<fingerprint>`
/// (TOML `[skeleton.3f2a…]` sections; JSON `"skeleton": {"3f2a…": {…}}`), the fingerprint
/// `bvhview info` prints. An error names the file, line and column.
pub fn parse_map_pairs(text: &str, name: &str) -> Result<MapPairs, Error> {
    let bad = |line: usize, column: usize, message: String| Error::Parse {
        path: name.to_string(),
        line,
        column,
        message,
    };
    let mut out = MapPairs::default();
    // A byte-order mark (Windows editors write one) is not part of the map.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim_start().starts_with('{') {
        let value: JsonEntries = serde_json::from_str(text).map_err(|e| {
            // serde_json ends its message with the place, which the error already leads with.
            let said = e.to_string();
            let place = format!(" at line {} column {}", e.line(), e.column());
            let said = said.strip_suffix(&place).unwrap_or(&said);
            bad(e.line(), e.column(), format!("not a JSON map: {said}"))
        })?;
        let pair = |key: String, value: JsonItem| match value {
            JsonItem::Name(target) => Ok((key, target)),
            JsonItem::Null => Ok((key, String::new())),
            JsonItem::Object(_) => Err(bad(
                line_of(text, &key),
                1,
                format!(
                    "{}: expected a target joint's name, found an object",
                    quoted(&key)
                ),
            )),
            JsonItem::Other(kind) => Err(bad(
                line_of(text, &key),
                1,
                format!(
                    "{}: expected a target joint's name, found {kind}",
                    quoted(&key)
                ),
            )),
        };
        for (key, value) in value.0 {
            match value {
                JsonItem::Object(rigs) if key == "stated" => {
                    for (fingerprint, fields) in rigs.0 {
                        let JsonItem::Object(fields) = fields else {
                            return Err(bad(
                                line_of(text, &fingerprint),
                                1,
                                format!(
                                    "stated {}: expected an object of units and up",
                                    quoted(&fingerprint)
                                ),
                            ));
                        };
                        let mut said = Vec::new();
                        for (field, value) in fields.0 {
                            let JsonItem::Name(value) = value else {
                                return Err(bad(
                                    line_of(text, &field),
                                    1,
                                    format!("{}: expected a string", quoted(&field)),
                                ));
                            };
                            said.push((field, value));
                        }
                        let stated = stated_of(&said)
                            .map_err(|why| bad(line_of(text, &fingerprint), 1, why))?;
                        out.stated.push((fingerprint, stated));
                    }
                }
                JsonItem::Object(skeletons) if key == "skeleton" => {
                    for (fingerprint, pairs) in skeletons.0 {
                        let JsonItem::Object(pairs) = pairs else {
                            return Err(bad(
                                line_of(text, &fingerprint),
                                1,
                                format!(
                                    "skeleton {}: expected an object of pairs",
                                    quoted(&fingerprint)
                                ),
                            ));
                        };
                        let pairs = pairs
                            .0
                            .into_iter()
                            .map(|(k, v)| pair(k, v))
                            .collect::<Result<Vec<_>, Error>>()?;
                        out.by_skeleton.push((fingerprint, pairs));
                    }
                }
                value => out.all.push(pair(key, value)?),
            }
        }
    } else {
        let value: toml::Table = toml::from_str(text).map_err(|e| {
            let (line, column) = e
                .span()
                .map(|span| position_of(text, span.start))
                .unwrap_or((1, 1));
            bad(line, column, format!("not a TOML map: {}", e.message()))
        })?;
        let pair = |key: String, value: toml::Value| match value {
            toml::Value::String(target) => Ok((key, target)),
            other => Err(bad(
                line_of(text, &key),
                1,
                format!(
                    "{}: expected a target joint's name in quotes, found {}",
                    quoted(&key),
                    other.type_str()
                ),
            )),
        };
        for (key, value) in value {
            match value {
                toml::Value::Table(rigs) if key == "stated" => {
                    for (fingerprint, fields) in rigs {
                        let toml::Value::Table(fields) = fields else {
                            return Err(bad(
                                line_of(text, &fingerprint),
                                1,
                                format!(
                                    "stated.{}: expected a table of units and up",
                                    quoted(&fingerprint)
                                ),
                            ));
                        };
                        let mut said = Vec::new();
                        for (field, value) in fields {
                            let toml::Value::String(value) = value else {
                                return Err(bad(
                                    line_of(text, &field),
                                    1,
                                    format!("{}: expected a string in quotes", quoted(&field)),
                                ));
                            };
                            said.push((field, value));
                        }
                        let stated = stated_of(&said)
                            .map_err(|why| bad(line_of(text, &fingerprint), 1, why))?;
                        out.stated.push((fingerprint, stated));
                    }
                }
                toml::Value::Table(skeletons) if key == "skeleton" => {
                    for (fingerprint, pairs) in skeletons {
                        let toml::Value::Table(pairs) = pairs else {
                            return Err(bad(
                                line_of(text, &fingerprint),
                                1,
                                format!(
                                    "skeleton.{}: expected a table of pairs",
                                    quoted(&fingerprint)
                                ),
                            ));
                        };
                        let pairs = pairs
                            .into_iter()
                            .map(|(k, v)| pair(k, v))
                            .collect::<Result<Vec<_>, Error>>()?;
                        out.by_skeleton.push((fingerprint, pairs));
                    }
                }
                value => out.all.push(pair(key, value)?),
            }
        }
    }
    Ok(out)
}

/// A `[stated.<fingerprint>]` section's fields: `units` (a unit's name or metres per unit) and
/// `up` (`y` or `z`); anything else is refused by name.
fn stated_of(fields: &[(String, String)]) -> Result<Stated, String> {
    let mut stated = Stated::default();
    for (field, value) in fields {
        match field.as_str() {
            "units" => {
                stated.units =
                    Some(crate::model::stance::Units::named(value).ok_or_else(|| {
                        format!(
                            "units {}: expected mm, cm, m, in, ft or metres per unit",
                            quoted(value)
                        )
                    })?);
            }
            "up" => {
                stated.up = Some(value.parse().map_err(|_| {
                    format!("up {}: expected y, z, x, -y, -z or -x", quoted(value))
                })?);
            }
            other => {
                return Err(format!(
                    "{}: a stated section holds units and up only",
                    quoted(other)
                ));
            }
        }
    }
    Ok(stated)
}

/// A JSON map's entries (or its `"skeleton"` section's, or one fingerprint's) in file order.
/// A key given twice in one object is refused where the second one is (serde_json's own map
/// would keep the last silently; TOML refuses it too).
pub(super) struct JsonEntries(Vec<(String, JsonItem)>);

/// A JSON map's value: a target joint's name, `null` (leave the joint out), an object (the
/// `"skeleton"` section, a fingerprint's pairs), or anything else, kept as what it is.
pub(super) enum JsonItem {
    Name(String),
    Null,
    Object(JsonEntries),
    Other(&'static str),
}

/// An object's entries, each key checked against those before it in a set (a list searched
/// for each key made 95,000 keys take 11 s).
fn entries_of<'de, A: serde::de::MapAccess<'de>>(mut map: A) -> Result<JsonEntries, A::Error> {
    let mut seen = std::collections::HashSet::new();
    let mut entries = Vec::new();
    while let Some(key) = map.next_key::<String>()? {
        if !seen.insert(key.clone()) {
            return Err(serde::de::Error::custom(format!(
                "{} is given twice",
                quoted(&key)
            )));
        }
        entries.push((key, map.next_value::<JsonItem>()?));
    }
    Ok(JsonEntries(entries))
}

impl<'de> serde::Deserialize<'de> for JsonEntries {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Entries;
        impl<'de> serde::de::Visitor<'de> for Entries {
            type Value = JsonEntries;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a JSON object of source and target joint names")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<JsonEntries, A::Error> {
                entries_of(map)
            }
        }
        deserializer.deserialize_map(Entries)
    }
}

impl<'de> serde::Deserialize<'de> for JsonItem {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Item;
        impl<'de> serde::de::Visitor<'de> for Item {
            type Value = JsonItem;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a target joint's name, null or an object")
            }
            fn visit_str<E>(self, v: &str) -> Result<JsonItem, E> {
                Ok(JsonItem::Name(v.to_string()))
            }
            fn visit_string<E>(self, v: String) -> Result<JsonItem, E> {
                Ok(JsonItem::Name(v))
            }
            fn visit_unit<E>(self) -> Result<JsonItem, E> {
                Ok(JsonItem::Null)
            }
            fn visit_none<E>(self) -> Result<JsonItem, E> {
                Ok(JsonItem::Null)
            }
            fn visit_bool<E>(self, _: bool) -> Result<JsonItem, E> {
                Ok(JsonItem::Other("true or false"))
            }
            fn visit_i64<E>(self, _: i64) -> Result<JsonItem, E> {
                Ok(JsonItem::Other("a number"))
            }
            fn visit_u64<E>(self, _: u64) -> Result<JsonItem, E> {
                Ok(JsonItem::Other("a number"))
            }
            fn visit_f64<E>(self, _: f64) -> Result<JsonItem, E> {
                Ok(JsonItem::Other("a number"))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<JsonItem, A::Error> {
                while seq.next_element::<serde::de::IgnoredAny>()?.is_some() {}
                Ok(JsonItem::Other("an array"))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<JsonItem, A::Error> {
                entries_of(map).map(JsonItem::Object)
            }
        }
        deserializer.deserialize_any(Item)
    }
}

pub(super) fn position_of(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

pub(super) fn line_of(text: &str, key: &str) -> usize {
    text.lines()
        .position(|l| l.contains(key))
        .map_or(1, |i| i + 1)
}

/// Reads `SRC=DST`.
pub fn parse_pair(text: &str) -> Option<(String, String)> {
    let (src, dst) = text.split_once('=')?;
    let unquote = |s: &str| s.trim().trim_matches('"').to_string();
    let src = unquote(src);
    (!src.is_empty()).then(|| (src, unquote(dst)))
}
