//! Map files: the TOML or JSON `--map` reads (and `--show-map` prints), and `SRC=DST` pairs.

use super::*;

/// Reads a map file: JSON (`{"source": "target", …}`) or TOML (`"source" = "target"` lines,
/// what `--show-map` prints). An error names the file, line and column.
pub fn parse_map(text: &str, name: &str) -> Result<Vec<(String, String)>, Error> {
    let bad = |line: usize, column: usize, message: String| Error::Parse {
        path: name.to_string(),
        line,
        column,
        message,
    };
    let table: Vec<(String, String)> = if text.trim_start().starts_with('{') {
        let value: JsonEntries = serde_json::from_str(text)
            .map_err(|e| bad(e.line(), e.column(), format!("not a JSON map: {e}")))?;
        let mut pairs = Vec::new();
        for (key, value) in value.0 {
            match value {
                serde_json::Value::String(target) => pairs.push((key, target)),
                serde_json::Value::Null => pairs.push((key, String::new())),
                other => {
                    return Err(bad(
                        line_of(text, &key),
                        1,
                        format!("{key:?}: expected a target joint's name, found {other}"),
                    ));
                }
            }
        }
        pairs
    } else {
        let value: toml::Table = toml::from_str(text).map_err(|e| {
            let (line, column) = e
                .span()
                .map(|span| position_of(text, span.start))
                .unwrap_or((1, 1));
            bad(line, column, format!("not a TOML map: {}", e.message()))
        })?;
        let mut pairs = Vec::new();
        for (key, value) in value {
            match value {
                toml::Value::String(target) => pairs.push((key, target)),
                other => {
                    return Err(bad(
                        line_of(text, &key),
                        1,
                        format!(
                            "{key:?}: expected a target joint's name in quotes, found {}",
                            other.type_str()
                        ),
                    ));
                }
            }
        }
        pairs
    };
    Ok(table)
}

/// A JSON map's entries in file order. A key given twice is refused where the second one is
/// (serde_json's own map would keep the last silently; TOML refuses it too).
pub(super) struct JsonEntries(Vec<(String, serde_json::Value)>);

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
                mut map: A,
            ) -> Result<JsonEntries, A::Error> {
                let mut entries: Vec<(String, serde_json::Value)> = Vec::new();
                while let Some(key) = map.next_key::<String>()? {
                    if entries.iter().any(|(k, _)| *k == key) {
                        return Err(serde::de::Error::custom(format!("{key:?} is given twice")));
                    }
                    let value = map.next_value()?;
                    entries.push((key, value));
                }
                Ok(JsonEntries(entries))
            }
        }
        deserializer.deserialize_map(Entries)
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
