//! `prism converge`: error falls with the budget, results land in CSV and charts, equal-error times against a
//! peer curve are interpolated correctly.

use crate::common::{prism, refs, scene_path, scratch};
use prism::converge::time_to_error;

#[test]
fn equal_error_time_interpolates_log_log() {
    // RMSE = 0.1 / sqrt(t): reaches 0.05 at t = 4 exactly, whatever the sample points around it.
    let curve: Vec<(f64, f64)> = [1.0, 2.0, 8.0, 16.0].iter().map(|&t: &f64| (t, 0.1 / t.sqrt())).collect();
    let t = time_to_error(&curve, 0.05).unwrap();
    assert!((t - 4.0).abs() < 1e-9, "{t}");
    assert_eq!(time_to_error(&curve, 0.001), None, "never reached");
    assert_eq!(time_to_error(&curve, 0.5), Some(1.0), "already below at the first point");
}

#[test]
fn converge_writes_falling_error_curves_and_compares_with_a_peer() {
    let dir = scratch("converge");
    let o = prism(&[
        "converge",
        scene_path("furnace.ron").to_str().unwrap(),
        "--reference",
        refs("furnace.exr").to_str().unwrap(),
        "--integrator",
        "envlight",
        "--integrator",
        "envlight(env_sampling: uniform, mis: false)",
        "--spp",
        "1,4,16",
        "--peer",
        refs("curves.csv").to_str().unwrap(),
        "--peer-scene",
        "furnace",
        "-o",
        dir.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("equal error RMSE"), "{err}");
    let csv = std::fs::read_to_string(dir.join("convergence.csv")).unwrap();
    let rows: Vec<Vec<String>> = csv.lines().skip(1).map(|l| l.split(',').map(String::from).collect()).collect();
    let ours: Vec<&Vec<String>> = rows.iter().filter(|r| r[0] == "\"envlight\"").collect();
    assert_eq!(ours.len(), 3);
    let rmse: Vec<f64> = ours.iter().map(|r| r[3].parse().unwrap()).collect();
    assert!(rmse[0] > rmse[1] && rmse[1] > rmse[2], "RMSE must fall with spp: {rmse:?}");
    assert!(rows.iter().any(|r| r[0].contains("peer")), "the peer curve is in the CSV");
    for chart in ["rmse_vs_time.svg", "rmse_vs_spp.svg"] {
        let svg = std::fs::read_to_string(dir.join(chart)).unwrap();
        assert_eq!(svg.matches("<polyline").count(), 3, "{chart}: two integrators and the peer");
    }
}
