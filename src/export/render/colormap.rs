//! Colours for a measured quantity (a distance in millimetres) and the round numbers a
//! scale is marked at: what a `diff` picture colours new geometry by.

use super::raster::Linear;

/// The colour at 0: blue (linear RGB).
pub const LOW: Linear = [0.02, 0.10, 0.85];
/// The colour halfway: green.
pub const MID: Linear = [0.05, 0.65, 0.10];
/// The colour at the top of the scale and beyond: red.
pub const HIGH: Linear = [0.85, 0.03, 0.02];
/// The colour of a value that is not a number (a point with nothing to compare to).
pub const MISSING: Linear = [0.30, 0.30, 0.30];

/// The colour of `value` on a scale from 0 (blue) through `max / 2` (green) to `max`
/// (red), linear between them; values below 0 are blue, above `max` red, a NaN
/// [`MISSING`] grey. A `max` that is not positive colours every value from 0 up red
/// (a scale of nothing: any distance is at its top).
pub fn distance_color(value: f64, max: f64) -> Linear {
    if value.is_nan() {
        return MISSING;
    }
    let t = if max > 0.0 && max.is_finite() {
        (value / max).clamp(0.0, 1.0)
    } else if value > 0.0 {
        1.0
    } else {
        0.0
    };
    let (a, b, s) = if t <= 0.5 {
        (LOW, MID, t * 2.0)
    } else {
        (MID, HIGH, (t - 0.5) * 2.0)
    };
    // Weighted so each end colour comes out exactly.
    std::array::from_fn(|i| (1.0 - s) * a[i] + s * b[i])
}

/// Round values from 0 to `max` to mark a scale at: steps of 1, 2 or 5 times a power of
/// ten, at most `count` + 1 marks and as many as fit. Empty for a `max` that is not a
/// positive finite number.
pub fn ticks(max: f64, count: usize) -> Vec<f64> {
    if !(max > 0.0 && max.is_finite()) || count == 0 {
        return Vec::new();
    }
    let rough = max / count as f64;
    let power = 10f64.powf(rough.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * power)
        .find(|s| *s >= rough)
        .unwrap_or(10.0 * power);
    let n = (max / step + 1e-9).floor() as usize;
    (0..=n).map(|i| i as f64 * step).collect()
}

/// A tick value as a label: no trailing zeros, at most 6 decimals (`0`, `0.25`, `10`).
pub fn tick_label(value: f64) -> String {
    let s = format!("{value:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_runs_from_blue_through_green_to_red() {
        assert_eq!(distance_color(0.0, 2.0), LOW);
        assert_eq!(distance_color(1.0, 2.0), MID);
        assert_eq!(distance_color(2.0, 2.0), HIGH);
        assert_eq!(distance_color(-1.0, 2.0), LOW, "below the scale");
        assert_eq!(distance_color(9.0, 2.0), HIGH, "beyond the scale");
        assert_eq!(distance_color(f64::NAN, 2.0), MISSING);
        assert_eq!(distance_color(0.5, 0.0), HIGH, "an empty scale");
        let quarter = distance_color(0.5, 2.0);
        for i in 0..3 {
            assert!((quarter[i] - (LOW[i] + MID[i]) / 2.0).abs() < 1e-12);
        }
    }

    #[test]
    fn ticks_are_round_numbers_up_to_the_maximum() {
        assert_eq!(ticks(1.0, 4), vec![0.0, 0.5, 1.0]);
        assert_eq!(ticks(10.0, 5), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(ticks(0.3, 5), vec![0.0, 0.1, 0.2, 0.30000000000000004]);
        assert!(ticks(0.0, 5).is_empty() && ticks(f64::NAN, 5).is_empty());
        assert_eq!(tick_label(0.30000000000000004), "0.3");
        assert_eq!(tick_label(10.0), "10");
        assert_eq!(tick_label(0.0), "0");
    }
}
