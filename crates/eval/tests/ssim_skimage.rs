//! SSIM against scikit-image's `structural_similarity` (gaussian_weights=True, sigma=1.5,
//! use_sample_covariance=False, data_range=1) on the fixture written by
//! `tools/ssim_fixture.py`: agreement to 1e-3 is required, and the two should in fact agree to
//! rounding.

use caustica_eval::ssim::mean_ssim;

#[test]
fn ssim_matches_scikit_image() {
    let text = include_str!("fixtures/ssim_skimage.txt");
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let mut cases = 0;
    while let Some(head) = lines.next() {
        let f: Vec<&str> = head.split_whitespace().collect();
        assert_eq!(f[0], "case");
        let (name, w, h): (&str, usize, usize) =
            (f[1], f[2].parse().unwrap(), f[3].parse().unwrap());
        let expected: f64 = f[4].parse().unwrap();
        let mut row = |tag: &str| -> Vec<f64> {
            let l = lines.next().unwrap();
            let mut it = l.split_whitespace();
            assert_eq!(it.next(), Some(tag));
            it.map(|v| v.parse().unwrap()).collect()
        };
        let (x, y) = (row("x"), row("y"));
        assert_eq!((x.len(), y.len()), (w * h, w * h));
        let got = mean_ssim(&x, &y, w, h, |_, _| true).unwrap();
        assert!(
            (got - expected).abs() < 1e-3,
            "{name}: caustica {got} vs scikit-image {expected}"
        );
        assert!(
            (got - expected).abs() < 1e-6,
            "{name}: {got} vs {expected} (beyond rounding)"
        );
        cases += 1;
    }
    assert_eq!(cases, 4);
}
