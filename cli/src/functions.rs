//! `--functions`: the groups of functions `gen` and `info` generate, as the command line spells
//! them (the keywords of a description's `functions:`).

use clap::builder::PossibleValuesParser;
use clap::Args;
use dyngen_codegen::{FunctionGroup, Functions, ALL_GROUPS};

#[derive(Args, Clone, Debug, Default)]
pub struct FunctionsArgs {
    /// `functions`: the groups of functions to generate besides kinematics and dynamics,
    /// comma-separated (`regressors,base_parameters`), or `all`. Default: what the
    /// description's `functions:` says, else every group up to 12 joints, and kinematics,
    /// dynamics, forward_dynamics and frames above.
    #[arg(long, value_name = "GROUPS", value_delimiter = ',', value_parser = keywords())]
    functions: Option<Vec<String>>,
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
}
