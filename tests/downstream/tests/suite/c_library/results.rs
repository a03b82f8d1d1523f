//! What the test programs wrote: `result <how> <prefix> <function> <frame>` blocks of one line
//! per output (`<name> <count> <values>`, every state's block in turn), and `metadata <prefix>`
//! blocks of the robot's sizes, names, parameters and limits.

use std::collections::BTreeMap;

/// One function's outputs at every state, as one program computed them.
#[derive(Debug)]
pub(super) struct Result {
    pub outputs: Vec<(String, Vec<f64>)>,
}

/// `(how, prefix, function, frame)` → its outputs.
pub(super) type Results = BTreeMap<(String, String, String, usize), Result>;

/// A robot's metadata, by line key: the rest of each line (names keep their spaces).
pub(super) type Metadata = BTreeMap<String, BTreeMap<String, Vec<String>>>;

fn numbers(fields: &[&str], line: &str) -> Vec<f64> {
    let count: usize = fields[1]
        .parse()
        .unwrap_or_else(|_| panic!("a count: {line:.80}"));
    let values: Vec<f64> = (fields[2..].iter())
        .map(|v| v.parse().unwrap_or_else(|_| panic!("a number {v}: {line:.80}")))
        .collect();
    assert_eq!(values.len(), count, "{line:.80}");
    values
}

/// The results and metadata of one program's file.
pub(super) fn parse(text: &str) -> (Results, Metadata) {
    let mut results = Results::new();
    let mut metadata = Metadata::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        let fields: Vec<&str> = line.split(' ').collect();
        match fields[0] {
            "result" => {
                let key = (
                    fields[1].to_owned(),
                    fields[2].to_owned(),
                    fields[3].to_owned(),
                    fields[4].parse().expect("a frame"),
                );
                let mut outputs = Vec::new();
                for line in lines.by_ref().take_while(|l| *l != "end") {
                    let fields: Vec<&str> = line.split(' ').collect();
                    outputs.push((fields[0].to_owned(), numbers(&fields, line)));
                }
                assert!(
                    results.insert(key.clone(), Result { outputs }).is_none(),
                    "{key:?} twice"
                );
            }
            "metadata" => {
                let entry = metadata.entry(fields[1].to_owned()).or_default();
                for line in lines.by_ref().take_while(|l| *l != "end") {
                    let (key, rest) = line.split_once(' ').expect("a key");
                    entry.entry(key.to_owned()).or_default().push(rest.to_owned());
                }
            }
            other => panic!("unexpected line {other:.80}"),
        }
    }
    (results, metadata)
}

/// The numbers of a metadata line `<key> <count> <values>`.
pub(super) fn metadata_numbers(rest: &str) -> Vec<f64> {
    let fields: Vec<&str> = std::iter::once("").chain(rest.split(' ')).collect();
    numbers(&fields, rest)
}
