use dieface::geom::*;
use glam::DVec3;
#[test]
fn smoke() {
    let pts: Vec<DVec3> = (0..7).map(|i| DVec3::new(i as f64, ((i*i) % 5) as f64, (i % 3) as f64)).collect();
    let c = NurbsCurve::new_rational(3, vec![0.,0.,0.,0.,0.2,0.5,0.5,1.,1.,1.,1.], pts, vec![1.,2.,0.5,1.,1.5,1.,0.7]).unwrap();
    let c2 = c.insert_knot(0.3, 2).unwrap();
    let c3 = c.refine(&[0.1, 0.1, 0.6, 0.7, 0.7]).unwrap();
    let c4 = c.elevate_degree(2).unwrap();
    let (l, r) = c.split_at(0.4).unwrap();
    for i in 0..=100 {
        let t = i as f64 / 100.0;
        let p = c.point_at(t);
        assert!((p - c2.point_at(t)).length() < 1e-12, "ins {t}");
        assert!((p - c3.point_at(t)).length() < 1e-12, "ref {t}");
        assert!((p - c4.point_at(t)).length() < 1e-12, "elev {t} {:?} {:?}", p, c4.point_at(t));
        let q = if t <= 0.4 { l.point_at(t) } else { r.point_at(t) };
        assert!((p - q).length() < 1e-12, "split {t}");
        // derivative vs finite difference
        let [_, d1, d2] = c.derivatives::<3>(t);
        let h = 1e-6;
        if t > 0.01 && t < 0.99 && (t-0.5).abs() > 0.01 && (t-0.2).abs() > 0.01 {
            let fd = (c.point_at(t + h) - c.point_at(t - h)) / (2.0 * h);
            assert!((fd - d1).length() < 1e-5 * d1.length().max(1.0), "d1 {t} {fd} {d1}");
            let fd2 = (c.derivative_at(t + h) - c.derivative_at(t - h)) / (2.0 * h);
            assert!((fd2 - d2).length() < 1e-4 * d2.length().max(1.0), "d2 {t} {fd2} {d2}");
        }
    }
    let circle_len = c.length();
    assert!(circle_len > 0.0);
    let t = c.parameter_at_length(circle_len * 0.3).unwrap();
    assert!((c.length_between(0.0, t) - circle_len * 0.3).abs() < 1e-9);
}
