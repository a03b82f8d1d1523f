//! Identification of a log too long to hold: the data file is read one line at a time, each
//! sample's base regressor is multiplied into per-joint normal equations
//! ([`NormalEquations`]) and dropped, so memory does not grow with the log.
//!
//! Missing velocities and accelerations are computed as [`prepare`](crate::prepare) computes
//! them, window by window: the zero-phase filter runs over a window of
//! [`IdentifyOptions::stream_window`]
//! samples with [`overlap`] samples of the signal on each side, and only the window's middle
//! is kept. The filter forgets where it started at the rate of its poles (a factor
//! `e^{−4.4 f_c/f_s}` per sample for the second-order Butterworth), so after the overlap of
//! `12 f_s/f_c` samples what differs from filtering the whole signal is below 10⁻²² of the
//! signal: the samples are those of the stacked path to rounding. The sampling rate comes
//! from a first pass over the file (first and last time, count), as the stacked path takes it
//! from the whole signal; that pass reads every line with every check, so a bad line is
//! reported before any work, with the message the stacked path gives.
//!
//! An input that can be read once only (the standard input `-`, a pipe such as `/dev/stdin`
//! or a named pipe) is read in one pass: the step is the mean of the first window's
//! ([`IdentifyOptions::stream_window`] samples, held until it is known), and every later step
//! is checked against it. Sampling uniform to rounding gives the stacked path's samples to
//! rounding; a bad line is reported when it is reached.

use crate::data::{read_once, Sample, SampleReader};
use crate::differentiate::{check_step, differences, filtfilt, padding};
use crate::error::IdentifyError;
use crate::least_squares::{estimate, BaseEstimate, Observations};
use crate::normal_equations::NormalEquations;
use crate::observation::BaseRegressorSource;
use crate::pipeline::IdentifyOptions;
use dyngen_model::model::Model;
use std::collections::VecDeque;
use std::path::Path;

/// How far a streaming identification has come, reported as it goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// 1: checking the file and finding its sampling rate (only when derivatives are
    /// computed); 2: accumulating the regressor.
    pub pass: usize,
    pub bytes_read: u64,
    pub file_bytes: u64,
    /// Samples multiplied into the normal equations.
    pub samples: usize,
}

/// A streaming least-squares estimate and what it was made from.
#[derive(Clone, Debug)]
pub struct StreamedEstimate {
    pub base: BaseEstimate,
    pub samples_used: usize,
    /// Whether q̇, q̈ were computed (filter and differences) rather than given.
    pub differentiated: bool,
}

/// Samples of the filter's memory on each side of a window.
pub(crate) fn overlap(rate: f64, cutoff: f64) -> usize {
    ((12.0 * rate / cutoff).ceil() as usize).max(padding(rate, cutoff))
}

/// Reports progress at most once per this many samples.
const PROGRESS_EVERY: usize = 10_000;

/// The weighted least squares of [`identify`](crate::identify) on the base regressor of
/// `source` (which must have `model`'s base parameters), over the data file `path` read
/// line by line. `progress` is called as the file is read.
pub fn estimate_streaming(
    model: &Model,
    source: &impl BaseRegressorSource,
    path: &Path,
    options: &IdentifyOptions,
    mut progress: impl FnMut(&Progress),
) -> Result<StreamedEstimate, IdentifyError> {
    let file_bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    let reader = SampleReader::open(path, model, true)?;
    let differentiated = !(reader.has_velocities() && reader.has_accelerations());
    let (n, b) = (model.dof(), source.base_names().len());
    let mut equations = NormalEquations::new(n, b);
    let mut report = |pass: usize, bytes_read: u64, samples: usize| {
        progress(&Progress {
            pass,
            bytes_read,
            file_bytes,
            samples,
        })
    };
    let add = |q: &[f64], qd: &[f64], qdd: &[f64], tau: &[f64], equations: &mut NormalEquations| {
        equations.push(&source.base_regressor(q, qd, qdd), tau);
    };
    if !differentiated {
        let mut reader = reader;
        while let Some(sample) = reader.next() {
            let s = sample?;
            let (qd, qdd, tau) = (s.qd.expect("qd"), s.qdd.expect("qdd"), s.tau.expect("tau"));
            add(&s.q, &qd, &qdd, &tau, &mut equations);
            if equations.samples().is_multiple_of(PROGRESS_EVERY) {
                report(2, reader.bytes_read(), equations.samples());
            }
        }
    } else {
        // The sampling step: from a first pass over the whole file, as the stacked path takes
        // it; or, from an input that can be read once only, from the first window's samples,
        // held until it is known.
        let mut reader = reader;
        let mut lead = Vec::new();
        let (step, count) = if read_once(path) {
            while lead.len() < options.stream_window.max(3) {
                match reader.next() {
                    Some(sample) => lead.push(sample?),
                    None => break,
                }
            }
            if lead.len() < 3 {
                return Err(IdentifyError::data(format!(
                    "{} samples: at least 3 are needed to compute velocities and accelerations",
                    lead.len()
                ))
                .in_file(path));
            }
            let span = lead[lead.len() - 1].time - lead[0].time;
            (span / (lead.len() - 1) as f64, None)
        } else {
            let timing = first_pass(model, path, &mut |bytes, k| report(1, bytes, k))?;
            report(1, file_bytes, 0);
            reader = SampleReader::open(path, model, true)?;
            (timing.step, Some(timing.count))
        };
        let rate = 1.0 / step;
        if !(options.cutoff > 0.0 && options.cutoff < 0.5 * rate) {
            return Err(IdentifyError::data(format!(
                "filter cutoff {} Hz must lie between 0 and half the sampling rate ({} Hz)",
                options.cutoff,
                0.5 * rate
            ))
            .in_file(path));
        }
        let pad = padding(rate, options.cutoff);
        let too_few = |count: usize| {
            IdentifyError::data(format!(
                "{count} samples: the filter's transients take {pad} at each end; give more samples or q̇ and q̈",
            ))
            .in_file(path)
        };
        if let Some(count) = count.filter(|&count| count <= 2 * pad) {
            return Err(too_few(count));
        }
        let mut windows = Windows {
            rate,
            cutoff: options.cutoff,
            pad,
            overlap: overlap(rate, options.cutoff),
            window: options.stream_window.max(1),
            count: count.unwrap_or(usize::MAX),
            buffer: VecDeque::new(),
            first: 0,
            next: pad,
        };
        let (mut k, mut previous) = (0, None);
        let mut lead = lead.into_iter();
        loop {
            let sample = match lead.next() {
                Some(sample) => sample,
                None => match reader.next() {
                    Some(sample) => sample?,
                    None => break,
                },
            };
            if let Some(p) = previous {
                check_step(sample.time - p, step, Some(sample.line)).map_err(|e| e.in_file(path))?;
            }
            previous = Some(sample.time);
            windows.push(sample, &mut |q, qd, qdd, tau| {
                add(q, qd, qdd, tau, &mut equations)
            });
            k += 1;
            if k % PROGRESS_EVERY == 0 {
                report(2, reader.bytes_read(), equations.samples());
            }
        }
        if count.is_none() {
            if k <= 2 * pad {
                return Err(too_few(k));
            }
            windows.count = k;
        }
        windows.finish(&mut |q, qd, qdd, tau| add(q, qd, qdd, tau, &mut equations));
    }
    let equations = equations.finished();
    report(2, file_bytes, equations.samples());
    if equations.samples() == 0 {
        return Err(IdentifyError::data("no samples: the file has a header line only").in_file(path));
    }
    let samples_used = equations.samples();
    let base = estimate(Observations::Accumulated(&equations), &source.base_names())?;
    Ok(StreamedEstimate {
        base,
        samples_used,
        differentiated,
    })
}

/// The file's sampling: count and mean step, as the stacked path computes them.
struct Timing {
    count: usize,
    step: f64,
}

/// Reads the time of every line for the count and the first and last time. A line whose time
/// is not plainly a later sample sends a full read from the start, which reports the first
/// problem of the file as [`read_csv`](crate::read_csv) does.
fn first_pass(
    model: &Model,
    path: &Path,
    progress: &mut dyn FnMut(u64, usize),
) -> Result<Timing, IdentifyError> {
    let mut reader = SampleReader::open(path, model, true)?;
    let (mut count, mut first, mut last) = (0usize, 0.0, 0.0);
    while let Some(time) = reader.next_time() {
        let Some(time) = time else {
            for sample in SampleReader::open(path, model, true)? {
                sample?;
            }
            return Err(IdentifyError::data("the file changed while it was read").in_file(path));
        };
        if count == 0 {
            first = time;
        }
        last = time;
        count += 1;
        if count % PROGRESS_EVERY == 0 {
            progress(reader.bytes_read(), 0);
        }
    }
    let step = (last - first) / (count - 1) as f64;
    Ok(Timing { count, step })
}

/// The zero-phase filter and differences run window by window over a stream of samples.
struct Windows {
    rate: f64,
    cutoff: f64,
    /// Samples dropped at each end of the log (the filter's transients), as the stacked path
    /// drops them.
    pad: usize,
    overlap: usize,
    window: usize,
    count: usize,
    buffer: VecDeque<Sample>,
    /// Index in the log of `buffer[0]`.
    first: usize,
    /// Index of the next sample to hand on.
    next: usize,
}

type Emit<'a> = dyn FnMut(&[f64], &[f64], &[f64], &[f64]) + 'a;

impl Windows {
    fn push(&mut self, sample: Sample, emit: &mut Emit<'_>) {
        self.buffer.push_back(sample);
        let before = self.next - self.first;
        if self.buffer.len() >= before + self.window + self.overlap {
            let end = self.first + self.buffer.len() - self.overlap;
            self.emit_until(end, emit);
            let keep_from = self.next.saturating_sub(self.overlap);
            while self.first < keep_from {
                self.buffer.pop_front();
                self.first += 1;
            }
        }
    }

    fn finish(&mut self, emit: &mut Emit<'_>) {
        self.emit_until(self.count - self.pad, emit);
    }

    /// Filters the buffer and hands on the samples from `next` up to `end` (exclusive).
    fn emit_until(&mut self, end: usize, emit: &mut Emit<'_>) {
        if end <= self.next {
            return;
        }
        let len = self.buffer.len();
        let n = self.buffer[0].q.len();
        let time: Vec<f64> = self.buffer.iter().map(|s| s.time).collect();
        let mut qd = vec![vec![0.0; n]; len];
        let mut qdd = vec![vec![0.0; n]; len];
        for j in 0..n {
            let x: Vec<f64> = self.buffer.iter().map(|s| s.q[j]).collect();
            let (d1, d2) = differences(&time, &filtfilt(&x, self.rate, self.cutoff));
            for k in 0..len {
                qd[k][j] = d1[k];
                qdd[k][j] = d2[k];
            }
        }
        for k in self.next - self.first..end - self.first {
            let s = &self.buffer[k];
            let velocity = s.qd.as_ref().unwrap_or(&qd[k]);
            emit(&s.q, velocity, &qdd[k], s.tau.as_ref().expect("tau"));
        }
        self.next = end;
    }
}
