//! `--functions`: the groups of functions `gen` and `info` generate, as the command line spells
//! them (the keywords of a description's `functions:`).

use clap::builder::PossibleValuesParser;
use clap::{Args, ValueEnum};
use dyngen_codegen::description::{Choices, CodeShape, FrameReferences};
use dyngen_codegen::{FunctionGroup, Functions, ALL_GROUPS};

#[derive(Args, Clone, Debug, Default)]
pub struct FunctionsArgs {
    /// `functions`: the groups of functions to generate besides kinematics and dynamics,
    /// comma-separated (`regressors,base_parameters`), or `all`. Default: what the
    /// description's `functions:` says, else every group up to 12 joints, and kinematics,
    /// dynamics, forward_dynamics and frames above.
    #[arg(long, value_name = "GROUPS", value_delimiter = ',', value_parser = keywords())]
    functions: Option<Vec<String>>,
    /// `frame_references`: which reference frames of the frame functions are straight-line
    /// code of their own: `all`, or `aligned` (`local_world_aligned`; `local` and `world`
    /// converted from it at run time, about a third of the frames' code). Default: `all` while
    /// the frames' code is small, `aligned` for many frames on a large robot.
    #[arg(long, value_enum, value_name = "CHOICE")]
    frame_references: Option<FrameReferencesArg>,
    /// `code_shape`: whether the functions that have a composed form (forward dynamics, `D⁻¹`
    /// and the derivatives of forward dynamics) are straight-line code (`flat`, the fastest) or
    /// computed from the robot's smaller functions through the tree factor of `D` (`composed`,
    /// no code of their own). Default: `flat` while a function's straight-line code is small, `composed` where it
    /// would be megabytes.
    #[arg(long, value_enum, value_name = "SHAPE")]
    code_shape: Option<CodeShapeArg>,
}

/// `--code-shape`: [`CodeShape`] as the command line spells it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum CodeShapeArg {
    Flat,
    Composed,
}

/// `--frame-references`: [`FrameReferences`] as the command line spells it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum FrameReferencesArg {
    All,
    Aligned,
}

/// Every group's keyword and `all`: clap refuses anything else as a usage error.
fn keywords() -> PossibleValuesParser {
    let mut names: Vec<&'static str> = FunctionGroup::ALL.iter().map(|g| g.keyword()).collect();
    names.push(ALL_GROUPS);
    PossibleValuesParser::new(names)
}

impl FunctionsArgs {
    /// The groups chosen, if any; an error names a group given without the one it needs.
    pub fn functions(&self) -> Result<Option<Functions>, String> {
        let Some(keywords) = &self.functions else {
            return Ok(None);
        };
        Functions::from_keywords(keywords.iter().map(String::as_str)).map(Some)
    }

    /// `choices` (the description's keys the other flags choose) with these flags' own: the
    /// groups, the frames' reference frames and the code shape.
    pub fn choose(&self, choices: Choices) -> Result<Choices, String> {
        Ok(Choices {
            functions: self.functions()?,
            frame_references: match self.frame_references {
                None => FrameReferences::Auto,
                Some(FrameReferencesArg::All) => FrameReferences::All,
                Some(FrameReferencesArg::Aligned) => FrameReferences::Aligned,
            },
            code_shape: match self.code_shape {
                None => CodeShape::Auto,
                Some(CodeShapeArg::Flat) => CodeShape::Flat,
                Some(CodeShapeArg::Composed) => CodeShape::Composed,
            },
            ..choices
        })
    }
}
