//! How a frame's name is spelled in generated code: a variant of the robot's `Frame` enum
//! (`panda_hand_tcp` → `PandaHandTcp`) and a part of function names (`panda_hand_tcp`).
//!
//! Two names may spell the same identifier (`link_1` and `Link1` are both `Link1`; `a-b` and
//! `a_b` both `AB` and `a_b`). [`frame_identifiers`] then tells them apart, deterministically,
//! over the whole list of a robot's frames in their order (the end-effector first):
//!
//! - a frame whose spellings no earlier frame uses keeps them;
//! - a later frame whose variant or snake-case spelling an earlier one already uses gets a
//!   suffix `n` on both: `_n` on the snake-case spelling, `n` on the variant (`_n` when the
//!   variant ends in a digit, as rustc spells `link1_2` in camel case: `Link1_2`), with `n`
//!   the smallest number from 2 up whose spellings no frame of the list has or was given.
//!
//! So `[link_1, Link1]` is `Link1`/`link_1` and `Link1_2`/`link1_2`, and `[a-b, a_b]` is
//! `AB`/`a_b` and `AB2`/`a_b_2`. The loader notes every suffix it gives; the generator names
//! the `Frame` variants and the frame functions with the same list, so they always agree.

use std::collections::HashSet;

/// The two Rust spellings of one frame name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameIdentifiers {
    /// `UpperCamelCase`: the enum variant.
    pub variant: String,
    /// `snake_case`: the part of the frame's function names.
    pub snake: String,
    /// The earlier frame (its index in the list) whose spelling this frame's name shares, when
    /// the spellings got a suffix to tell them apart.
    pub suffixed_after: Option<usize>,
}

/// The spellings of every frame in `names` (a robot's frames, in order), told apart as the
/// module docs say.
pub fn frame_identifiers<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<FrameIdentifiers> {
    let spelled: Vec<(String, String)> = names.into_iter().map(spellings).collect();
    let written_variants: HashSet<&str> = spelled.iter().map(|(v, _)| v.as_str()).collect();
    let written_snakes: HashSet<&str> = spelled.iter().map(|(_, s)| s.as_str()).collect();
    let mut out: Vec<FrameIdentifiers> = Vec::with_capacity(spelled.len());
    for (variant, snake) in &spelled {
        let earlier = out
            .iter()
            .position(|id| id.variant == *variant || id.snake == *snake);
        let Some(earlier) = earlier else {
            out.push(FrameIdentifiers {
                variant: variant.clone(),
                snake: snake.clone(),
                suffixed_after: None,
            });
            continue;
        };
        let free = |v: &str, s: &str| {
            !written_variants.contains(v)
                && !written_snakes.contains(s)
                && !out.iter().any(|id| id.variant == v || id.snake == s)
        };
        let (variant, snake) = (2..)
            .map(|n| {
                let joint = match variant.ends_with(|c: char| c.is_ascii_digit()) {
                    true => "_",
                    false => "",
                };
                (format!("{variant}{joint}{n}"), format!("{snake}_{n}"))
            })
            .find(|(v, s)| free(v, s))
            .expect("finitely many names are taken");
        out.push(FrameIdentifiers {
            variant,
            snake,
            suffixed_after: Some(earlier),
        });
    }
    out
}

/// The spellings of one name on its own: its ASCII letters and digits, split at everything
/// else (and prefixed when it would start with a digit or be empty). A part written in
/// capitals is a word, not an acronym to keep (`FL_FOOT` → `FlFoot`, as Rust spells
/// variants); a part in mixed case keeps its inner capitals (`camelCase` → `CamelCase`).
fn spellings(name: &str) -> (String, String) {
    let parts: Vec<&str> = name
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|p| !p.is_empty())
        .collect();
    let mut variant: String = parts
        .iter()
        .map(|p| {
            let word = match p.chars().any(|c| c.is_ascii_lowercase()) {
                true => p.to_string(),
                false => p.to_ascii_lowercase(),
            };
            let mut chars = word.chars();
            let first = chars.next().map(|c| c.to_ascii_uppercase());
            first.into_iter().chain(chars).collect::<String>()
        })
        .collect();
    let mut snake = parts
        .iter()
        .map(|p| p.to_ascii_lowercase())
        .collect::<Vec<_>>()
        .join("_");
    if variant.is_empty() || variant.starts_with(|c: char| c.is_ascii_digit()) {
        variant.insert_str(0, "Frame");
        snake.insert_str(0, "frame_");
    }
    (variant, snake)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spelled(names: &[&str]) -> Vec<(String, String)> {
        frame_identifiers(names.iter().copied())
            .into_iter()
            .map(|id| (id.variant, id.snake))
            .collect()
    }

    fn pairs(p: &[(&str, &str)]) -> Vec<(String, String)> {
        p.iter().map(|(v, s)| (v.to_string(), s.to_string())).collect()
    }

    #[test]
    fn names_become_rust_identifiers() {
        let names = [
            "panda_hand_tcp",
            "link_3.0_tip",
            "7th-Link",
            "FL_FOOT",
            "l_sole2_IMU",
            "..",
        ];
        assert_eq!(
            spelled(&names),
            pairs(&[
                ("PandaHandTcp", "panda_hand_tcp"),
                ("Link30Tip", "link_3_0_tip"),
                ("Frame7thLink", "frame_7th_link"),
                ("FlFoot", "fl_foot"),
                ("LSole2Imu", "l_sole2_imu"),
                ("Frame", "frame_"),
            ])
        );
        assert!(frame_identifiers(names)
            .iter()
            .all(|id| id.suffixed_after.is_none()));
    }

    #[test]
    fn names_spelled_alike_get_suffixes_in_order() {
        let ids = frame_identifiers(["tool0", "link_1", "Link1"]);
        assert_eq!(
            ids.iter()
                .map(|id| (id.variant.as_str(), id.snake.as_str()))
                .collect::<Vec<_>>(),
            [("Tool0", "tool0"), ("Link1", "link_1"), ("Link1_2", "link1_2")]
        );
        assert_eq!(ids[2].suffixed_after, Some(1));
        // Either spelling alike is enough; the suffix joins a letter without `_`.
        assert_eq!(
            spelled(&["a-b", "a_b", "ab_c", "AbC"]),
            pairs(&[
                ("AB", "a_b"),
                ("AB2", "a_b_2"),
                ("AbC", "ab_c"),
                ("AbC2", "abc_2")
            ])
        );
        // A suffix never takes a spelling some frame has, nor one given before.
        assert_eq!(
            spelled(&["x", "X", "x_2", "x-3", "X."]),
            pairs(&[
                ("X", "x"),
                ("X4", "x_4"),
                ("X2", "x_2"),
                ("X3", "x_3"),
                ("X5", "x_5")
            ])
        );
    }
}
