//! How a frame's name is spelled in generated code: a variant of the robot's `Frame` enum
//! (`panda_hand_tcp` → `PandaHandTcp`) and a part of function names (`panda_hand_tcp`).

/// The two Rust spellings of one frame name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameIdentifiers {
    /// `UpperCamelCase`: the enum variant.
    pub variant: String,
    /// `snake_case`: the part of the frame's function names.
    pub snake: String,
}

/// The spellings of `name`: its ASCII letters and digits, split at everything else (and
/// prefixed when it would start with a digit or be empty). A part written in capitals is a
/// word, not an acronym to keep (`FL_FOOT` → `FlFoot`, as Rust spells variants); a part in
/// mixed case keeps its inner capitals (`camelCase` → `CamelCase`).
pub fn frame_identifiers(name: &str) -> FrameIdentifiers {
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
    FrameIdentifiers { variant, snake }
}

/// The first pair of names (earlier, later) whose spellings in generated code coincide.
pub fn clashing_frame_names<'a>(names: &[&'a str]) -> Option<(&'a str, &'a str, String)> {
    let ids: Vec<FrameIdentifiers> = names.iter().map(|n| frame_identifiers(n)).collect();
    for (k, id) in ids.iter().enumerate() {
        for (j, other) in ids[..k].iter().enumerate() {
            if id.variant == other.variant || id.snake == other.snake {
                let spelled = match id.variant == other.variant {
                    true => format!("`Frame::{}`", id.variant),
                    false => format!("`{}`", id.snake),
                };
                return Some((names[j], names[k], spelled));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_become_rust_identifiers() {
        let id = frame_identifiers("panda_hand_tcp");
        assert_eq!(
            (id.variant.as_str(), id.snake.as_str()),
            ("PandaHandTcp", "panda_hand_tcp")
        );
        let id = frame_identifiers("link_3.0_tip");
        assert_eq!(
            (id.variant.as_str(), id.snake.as_str()),
            ("Link30Tip", "link_3_0_tip")
        );
        let id = frame_identifiers("7th-Link");
        assert_eq!(
            (id.variant.as_str(), id.snake.as_str()),
            ("Frame7thLink", "frame_7th_link")
        );
        let id = frame_identifiers("FL_FOOT");
        assert_eq!((id.variant.as_str(), id.snake.as_str()), ("FlFoot", "fl_foot"));
        let id = frame_identifiers("l_sole2_IMU");
        assert_eq!(
            (id.variant.as_str(), id.snake.as_str()),
            ("LSole2Imu", "l_sole2_imu")
        );
        let id = frame_identifiers("..");
        assert_eq!((id.variant.as_str(), id.snake.as_str()), ("Frame", "frame_"));
    }

    #[test]
    fn clashes_are_found_in_either_spelling() {
        assert_eq!(clashing_frame_names(&["tool0", "flange"]), None);
        let (a, b, _) = clashing_frame_names(&["tool", "a-b", "a_b"]).expect("a clash");
        assert_eq!((a, b), ("a-b", "a_b"));
        let (a, b, _) = clashing_frame_names(&["ab_c", "AbC"]).expect("a clash");
        assert_eq!((a, b), ("ab_c", "AbC"));
    }
}
