//! The functions of a source file and their lengths. A function runs from
//! its `fn` line to the brace that closes its body, braces inside comments,
//! strings and character literals not counted.

use std::path::Path;

pub const MAX_FUNCTION_LINES: usize = 80;

/// The body's braces of `text`, blanked: comments, strings and characters
/// turned into spaces, so that only code braces are left.
pub fn code_only(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        let skip_to = if c == '/' && next == Some('/') {
            let rest = chars[i..].iter().position(|&c| c == '\n');
            Some(rest.map_or(chars.len(), |n| i + n))
        } else if c == '"' {
            closing_quote(&chars, i + 1)
        } else if c == 'r' && matches!(next, Some('"') | Some('#')) && !ident_before(&chars, i) {
            raw_string_end(&chars, i + 1)
        } else if c == '\'' {
            char_literal_end(&chars, i)
        } else {
            None
        };
        match skip_to {
            Some(end) => {
                let blanked = chars[i..end]
                    .iter()
                    .map(|&c| if c == '\n' { c } else { ' ' });
                out.extend(blanked);
                i = end;
            }
            None => {
                out.push(c);
                i += 1;
            }
        }
    }
    out
}

pub fn ident_before(chars: &[char], i: usize) -> bool {
    i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_')
}

/// The index after the `"` closing a string whose text starts at `from`.
pub fn closing_quote(chars: &[char], from: usize) -> Option<usize> {
    let mut i = from;
    while i < chars.len() {
        match chars[i] {
            '\\' => i += 2,
            '"' => return Some(i + 1),
            _ => i += 1,
        }
    }
    Some(chars.len())
}

/// The index after a raw string `r#…"…"#…` whose hashes start at `from`.
pub fn raw_string_end(chars: &[char], from: usize) -> Option<usize> {
    let hashes = chars[from..].iter().take_while(|&&c| c == '#').count();
    if chars.get(from + hashes) != Some(&'"') {
        return None;
    }
    let mut i = from + hashes + 1;
    while i < chars.len() {
        if chars[i] == '"'
            && chars[i + 1..]
                .iter()
                .take(hashes)
                .filter(|&&c| c == '#')
                .count()
                == hashes
        {
            return Some(i + 1 + hashes);
        }
        i += 1;
    }
    Some(chars.len())
}

/// The index after a character literal at `at` (`'x'`, `'\n'`); none for a
/// lifetime.
pub fn char_literal_end(chars: &[char], at: usize) -> Option<usize> {
    match (chars.get(at + 1), chars.get(at + 2), chars.get(at + 3)) {
        (Some('\\'), _, _) => chars[at + 2..]
            .iter()
            .position(|&c| c == '\'')
            .map(|n| at + 3 + n),
        (Some(_), Some('\''), _) => Some(at + 3),
        _ => None,
    }
}

/// (name, first line, lines) of every function in `text` with a body.
pub fn functions(text: &str) -> Vec<(String, usize, usize)> {
    let code = code_only(text);
    let lines: Vec<&str> = code.lines().collect();
    let mut found = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        let Some(at) = line.find("fn ").filter(|&at| {
            let before = line[..at].trim();
            before.is_empty()
                || before.split_whitespace().all(|w| {
                    ["pub", "const", "async", "unsafe", "extern"].contains(&w)
                        || w.starts_with("pub(")
                })
        }) else {
            continue;
        };
        let name: String = line[at + 3..]
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let mut depth = 0usize;
        let mut opened = false;
        'scan: for (end, body_line) in lines.iter().enumerate().skip(start) {
            let from = if end == start { at } else { 0 };
            for c in body_line[from..].chars() {
                match c {
                    ';' if !opened && depth == 0 => break 'scan, // no body
                    '{' => {
                        depth += 1;
                        opened = true;
                    }
                    '}' => {
                        depth -= 1;
                        if opened && depth == 0 {
                            found.push((name.clone(), start + 1, end - start + 1));
                            break 'scan;
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    found
}

pub fn rust_files(dir: &Path, files: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, files);
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
}
