//! Readable names of base parameters, e.g. `"Izz[link2] + Iyy[link3] + 0.0625·m[link3] + …"`.

/// Most terms a name lists before it ends in `+ …`.
pub const MAX_TERMS_IN_NAME: usize = 5;

/// A coefficient as a person reads it: the shortest decimal that round-trips when it has at most
/// eight significant digits (exact geometry such as `0.0625`), else six significant digits.
pub fn format_coefficient(c: f64) -> String {
    let shortest = format!("{c}");
    let digits = shortest
        .trim_start_matches(['-', '0', '.'])
        .replace('.', "")
        .len();
    if digits <= 8 && !shortest.contains('e') {
        return shortest;
    }
    let magnitude = c.abs().log10().floor() as i32;
    if !(-4..6).contains(&magnitude) {
        return format!("{c:.5e}");
    }
    let decimals = (5 - magnitude).max(0) as usize;
    let s = format!("{c:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    };
    s
}

/// The name of one base parameter from its terms `(standard index, coefficient)`, the kept
/// parameter first: the kept parameter, then the folded ones by decreasing magnitude of the
/// coefficient to nine digits (ties in parameter order: coefficients that are equal but for
/// rounding keep one order), at most [`MAX_TERMS_IN_NAME`] in all.
pub fn base_parameter_name(terms: &[(usize, f64)], standard_names: &[String]) -> String {
    let Some((&(first, _), rest)) = terms.split_first() else {
        return String::new();
    };
    let mut folded: Vec<(usize, f64)> = rest.to_vec();
    let magnitude = |c: f64| format!("{:.8e}", c.abs()).parse::<f64>().unwrap_or(c.abs());
    folded.sort_by(|a, b| magnitude(b.1).total_cmp(&magnitude(a.1)).then(a.0.cmp(&b.0)));
    let mut name = standard_names[first].clone();
    for (shown, &(k, c)) in folded.iter().enumerate() {
        if shown + 1 >= MAX_TERMS_IN_NAME {
            name += " + …";
            break;
        }
        let sign = if c < 0.0 { " − " } else { " + " };
        name += sign;
        if c.abs() != 1.0 {
            name += &format_coefficient(c.abs());
            name += "·";
        }
        name += &standard_names[k];
    }
    name
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficients_read_as_exact_decimals_or_six_digits() {
        assert_eq!(format_coefficient(0.0625), "0.0625");
        assert_eq!(format_coefficient(2.0), "2");
        assert_eq!(format_coefficient(0.04515625), "0.04515625");
        assert_eq!(format_coefficient(0.1 + 0.2), "0.3");
        assert_eq!(format_coefficient(std::f64::consts::PI), "3.14159");
        assert_eq!(format_coefficient(1.234e-7), "0.0000001234");
        assert_eq!(format_coefficient(1.2345678912e-7), "1.23457e-7");
    }

    #[test]
    fn names_list_the_kept_parameter_then_the_largest_folded_terms() {
        let names: Vec<String> = ["a", "b", "c", "d", "e", "f", "g"].map(String::from).to_vec();
        assert_eq!(
            base_parameter_name(&[(0, 1.0), (1, 0.5), (2, -1.0)], &names),
            "a − c + 0.5·b"
        );
        let many: Vec<(usize, f64)> = (0..7).map(|k| (k, 1.0)).collect();
        assert_eq!(base_parameter_name(&many, &names), "a + b + c + d + e + …");
    }
}
