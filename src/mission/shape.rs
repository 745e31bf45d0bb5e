//! What a file is when it is not a mission, said plainly.
//!
//! A mission is read with `deny_unknown_fields`, so whatever is not a mission
//! would otherwise be reported as the first field that does not fit: an empty file
//! as "missing field `name`", a plan file as "unknown field `makespan_steps`", a
//! sentence of prose as a type error. Before the mission is deserialized, the
//! text is read as plain YAML and its shape is looked at: broken YAML, an empty
//! file, something other than a mapping, and the files swarmctl itself writes
//! are each named for what they are.

use super::error::Problem;
use yaml_serde::Value;

/// The top-level keys every mission has.
const MISSION_KEYS: [&str; 4] = ["name", "world", "limits", "groups"];

/// The problem with `text` as a mission file if it is not YAML, is empty, is not
/// a mapping, is one of swarmctl's other files, or has none of a mission's keys;
/// `None` when it looks like a mission (its fields are checked later).
pub(super) fn problem(text: &str) -> Option<Problem> {
    let value: Value = match yaml_serde::from_str(text) {
        Ok(value) => value,
        Err(e) => return Some(syntax_problem(&e)),
    };
    let whole = |message: String| Some(Problem::new("", message));
    match &value {
        Value::Null => whole(
            "the file is empty: a mission needs name, world, limits and groups (`swarmctl template` prints a commented one)"
                .into(),
        ),
        Value::Mapping(map) => {
            let has = |key: &str| map.contains_key(key);
            if has("makespan_steps") && has("drones") {
                return whole(
                    "this is a plan file (written by `swarmctl plan -o`), not a mission: fly it with `swarmctl fly MISSION --plan PLAN.json`"
                        .into(),
                );
            }
            if has("summary") && has("drones") && has("events") {
                return whole(
                    "this is a flight log (written by `swarmctl fly`), not a mission: replay it with `swarmctl replay FLIGHT.json`"
                        .into(),
                );
            }
            if MISSION_KEYS.iter().any(|k| has(k)) {
                return None;
            }
            let found: Vec<String> = map.keys().take(5).map(describe_key).collect();
            whole(format!(
                "not a mission: none of name, world, limits and groups at the top level (found {})",
                found.join(", ")
            ))
        }
        other => whole(format!(
            "not a YAML mapping: the file is {}, but a mission is a mapping with name, world, limits and groups",
            kind(other)
        )),
    }
}

/// A YAML syntax error as one, with the opening bracket of an unclosed flow
/// collection named: the parser reports where it gave up, often on a later line.
fn syntax_problem(error: &yaml_serde::Error) -> Problem {
    let text = error.to_string();
    let line_column = error.location().map(|l| (l.line(), l.column()));
    let opened = [("flow sequence", '['), ("flow mapping", '{')]
        .into_iter()
        .find_map(|(what, bracket)| {
            let at = text.find(&format!("while parsing a {what} at line "))?;
            let tail = &text[at..];
            let (line, column) = numbers_after(tail, " at line ", " column ")?;
            Some((bracket, line, column))
        });
    let message = match opened {
        Some((bracket, line, column)) => {
            let close = if bracket == '[' { ']' } else { '}' };
            format!(
                "not valid YAML: unclosed `{bracket}` opened at {line}:{column} (a `{close}` or a `,` is missing)"
            )
        }
        None => format!("not valid YAML: {}", first_clause(&text)),
    };
    Problem {
        path: String::new(),
        message,
        line_column,
    }
}

/// The parser's message up to its location, which the problem carries apart.
fn first_clause(text: &str) -> &str {
    text.split(" at line ").next().unwrap_or(text)
}

/// The two numbers after `first` and `second` in `text`: `(L, C)` of "at line L column C".
fn numbers_after(text: &str, first: &str, second: &str) -> Option<(usize, usize)> {
    let rest = &text[text.find(first)? + first.len()..];
    let digits = |s: &str| -> Option<(usize, usize)> {
        let end = s.find(|c: char| !c.is_ascii_digit()).unwrap_or(s.len());
        Some((s[..end].parse().ok()?, end))
    };
    let (line, end) = digits(rest)?;
    let rest = rest[end..].strip_prefix(second)?;
    let (column, _) = digits(rest)?;
    Some((line, column))
}

fn describe_key(key: &Value) -> String {
    match key {
        Value::String(s) => {
            let short: String = s.chars().take(40).collect();
            format!("{short:?}")
        }
        other => kind(other).to_string(),
    }
}

fn kind(value: &Value) -> &'static str {
    match value {
        Value::Null => "empty",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a line of text",
        Value::Sequence(_) => "a list",
        Value::Mapping(_) => "a mapping",
        Value::Tagged(_) => "a tagged value",
    }
}

#[cfg(test)]
mod tests {
    use super::problem;

    fn message(text: &str) -> String {
        problem(text).map(|p| p.message).unwrap_or_default()
    }

    #[test]
    fn files_that_are_not_missions_are_named_for_what_they_are() {
        assert!(message("").starts_with("the file is empty"));
        assert!(message("# only a comment\n").starts_with("the file is empty"));
        assert!(
            message("This is not a mission.")
                .starts_with("not a YAML mapping: the file is a line of text")
        );
        assert!(message("- 1\n- 2\n").starts_with("not a YAML mapping: the file is a list"));
        assert!(
            message(r#"{"mission": "m", "makespan_steps": 3, "drones": []}"#)
                .starts_with("this is a plan file")
        );
        assert!(
            message("summary: {}\ndrones: []\nevents: []\n").starts_with("this is a flight log")
        );
        assert!(
            message("hello: world\n")
                .starts_with("not a mission: none of name, world, limits and groups")
        );
        assert_eq!(problem("name: m\nworld: {}\n"), None);
    }

    #[test]
    fn an_unclosed_bracket_is_named_where_it_opened() {
        let p = problem("name: m\nlimits:\n  x: [1, 2\ngroups: []\n").expect("a problem");
        assert!(
            p.message
                .starts_with("not valid YAML: unclosed `[` opened at 3:6"),
            "{}",
            p.message
        );
        assert!(p.line_column.is_some());
    }
}
