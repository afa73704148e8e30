//! Parsing a PLY header: the format line, the elements and their properties, comments and obj_info.

use super::*;

/// The header of `bytes`, or `(line, message)` (line 0: not a PLY file at all).
pub(super) fn parse_header(bytes: &[u8]) -> Result<Header, (usize, String)> {
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut at = 0usize;
    let mut line = 0usize;
    loop {
        let rest = bytes.get(at..).unwrap_or_default();
        if rest.is_empty() {
            return Err(match line {
                0 => (0, "not a PLY file: it is empty".into()),
                _ => (line, "the header has no `end_header` line".into()),
            });
        }
        let len = rest.iter().position(|&c| c == b'\n').unwrap_or(rest.len());
        let raw = &rest[..len];
        at = (at + len + 1).min(bytes.len());
        line += 1;
        let text = crate::files::text(raw);
        let mut words = text.split_ascii_whitespace();
        let keyword = words.next().unwrap_or("");
        if line == 1 {
            if keyword != "ply" || words.next().is_some() {
                return Err((
                    0,
                    "not a PLY file: it does not start with a `ply` line".into(),
                ));
            }
            continue;
        }
        let shown = |w: &str| w.chars().take(24).collect::<String>();
        match keyword {
            "" | "comment" | "obj_info" => {}
            "format" => {
                if format.is_some() {
                    return Err((line, "a second `format` line".into()));
                }
                let f = match words.next() {
                    Some("ascii") => Format::Ascii,
                    Some("binary_little_endian") => Format::Little,
                    Some("binary_big_endian") => Format::Big,
                    other => {
                        return Err((
                            line,
                            format!(
                                "unknown format `{}` (expected ascii, binary_little_endian or binary_big_endian)",
                                shown(other.unwrap_or(""))
                            ),
                        ))
                    }
                };
                match words.next() {
                    Some("1.0" | "1") => {}
                    other => {
                        return Err((
                            line,
                            format!(
                                "unsupported PLY version `{}` (expected 1.0)",
                                shown(other.unwrap_or(""))
                            ),
                        ))
                    }
                }
                format = Some(f);
            }
            "element" => {
                let (Some(name), Some(count), None) = (words.next(), words.next(), words.next())
                else {
                    return Err((line, "expected `element NAME COUNT`".into()));
                };
                let count = count.parse::<u64>().map_err(|_| {
                    (
                        line,
                        format!(
                            "element `{}`: `{}` is not a count",
                            shown(name),
                            shown(count)
                        ),
                    )
                })?;
                elements.push(Element {
                    name: name.to_owned(),
                    count,
                    props: Vec::new(),
                    line,
                });
            }
            "property" => {
                let Some(element) = elements.last_mut() else {
                    return Err((line, "`property` before any `element`".into()));
                };
                let ty = |w: Option<&str>| {
                    let w = w.unwrap_or("");
                    Scalar::parse(w)
                        .ok_or_else(|| (line, format!("unknown property type `{}`", shown(w))))
                };
                let first = words.next();
                let kind = if first == Some("list") {
                    let count = ty(words.next())?;
                    let item = ty(words.next())?;
                    if count.is_float() {
                        return Err((line, "a list's count type must be an integer type".into()));
                    }
                    Kind::List { count, item }
                } else {
                    Kind::Scalar(ty(first)?)
                };
                let (Some(name), None) = (words.next(), words.next()) else {
                    return Err((
                        line,
                        "expected `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME`"
                            .into(),
                    ));
                };
                element.props.push(Property {
                    name: name.to_owned(),
                    kind,
                });
            }
            "end_header" => {
                let Some(format) = format else {
                    return Err((line, "`end_header` before any `format` line".into()));
                };
                return Ok(Header {
                    format,
                    elements,
                    body: at,
                    lines: line,
                });
            }
            other => return Err((line, format!("unknown header keyword `{}`", shown(other)))),
        }
    }
}
