//! Cluster optics against independent numbers (DESIGN §4, §10): thin-film optics closed
//! forms, energy conservation, Bragg–Snell, stop-band widths and coupled-wave theory.

use opalray::optics::tmm::{periodic_rt, stack_rt, CharMatrix, Layer};
use opalray::optics::{bragg_wavelength_air_nm, cos_inside_from_air, ClusterStack, Polarization};
use opalray::scene::CrystalConfig;

const POLS: [Polarization; 2] = [Polarization::S, Polarization::P];

fn crystal(n_matrix: f64) -> CrystalConfig {
    CrystalConfig {
        n_matrix,
        ..CrystalConfig::default()
    }
}

/// Relative width of the first-order stop band at normal incidence (band edges of the
/// infinite crystal).
fn relative_stop_band(stack: &ClusterStack) -> f64 {
    let (lo, hi) = stack.stop_band_nm(1.0, Polarization::S).expect("a gap");
    2.0 * (hi - lo) / (hi + lo)
}

/// Wavelength and value of the largest unpolarised R on a uniform scan.
fn peak(stack: &ClusterStack, cos_theta: f64, from_nm: f64, to_nm: f64, step: f64) -> (f64, f64) {
    let at = stack.at(cos_theta);
    let n = ((to_nm - from_nm) / step) as usize;
    (0..=n)
        .map(|i| from_nm + i as f64 * step)
        .map(|wl| (wl, at.rt_unpolarized(wl).0))
        .fold((0.0, -1.0), |best, x| if x.1 > best.1 { x } else { best })
}

#[test]
fn quarter_wave_stack_matches_its_closed_form() {
    // DESIGN §10 and Macleod, Thin-Film Optical Filters §5.2: (HL)^N on a substrate at the
    // design wavelength, normal incidence:
    // R = ((1 − (n0/ns)(nL/nH)^2N) / (1 + (n0/ns)(nL/nH)^2N))²;
    // n_H 2.3, n_L 1.38, n0 1, ns 1.52: N = 1 → 0.3807, N = 3 → 0.8844.
    let (n_h, n_l, n0, n_s, design_nm) = (2.3f64, 1.38f64, 1.0f64, 1.52f64, 550.0);
    let closed = |n: i32| {
        let y = (n0 / n_s) * (n_l / n_h).powi(2 * n);
        ((1.0 - y) / (1.0 + y)).powi(2)
    };
    assert!((closed(1) - 0.3807).abs() < 5e-5 && (closed(3) - 0.8844).abs() < 5e-5);
    for n in 1..=8 {
        let layers: Vec<Layer> = (0..n)
            .flat_map(|_| {
                [
                    Layer {
                        n: n_h,
                        thickness_nm: design_nm / (4.0 * n_h),
                    },
                    Layer {
                        n: n_l,
                        thickness_nm: design_nm / (4.0 * n_l),
                    },
                ]
            })
            .collect();
        for pol in POLS {
            let (r, _) = stack_rt(n0, &layers, n_s, 0.0, design_nm, pol);
            assert!(
                (r - closed(n)).abs() < 1e-6,
                "N = {n}: R = {r}, closed {}",
                closed(n)
            );
        }
    }
}

#[test]
fn single_film_matches_the_airy_formula() {
    // Born & Wolf, Principles of Optics §1.6.4 / Hecht §9.7: for one film between n0 and n2,
    // R = (r01² + r12² + 2 r01 r12 cos 2δ) / (1 + r01² r12² + 2 r01 r12 cos 2δ),
    // δ = 2π n1 h cos θ1 / λ, with the Fresnel amplitude coefficients of each interface.
    let (n0, n2, h) = (1.0, 1.52, 137.0);
    for n1 in [1.38, 1.8, 2.3] {
        for deg in [0.0f64, 20.0, 45.0, 70.0] {
            let t0 = deg.to_radians();
            let sin_at = |n: f64| n0 * t0.sin() / n;
            let cos_at = |n: f64| (1.0 - sin_at(n).powi(2)).sqrt();
            let (c0, c1, c2) = (cos_at(n0), cos_at(n1), cos_at(n2));
            for pol in POLS {
                let fresnel = |na: f64, ca: f64, nb: f64, cb: f64| match pol {
                    Polarization::S => (na * ca - nb * cb) / (na * ca + nb * cb),
                    Polarization::P => (nb * ca - na * cb) / (nb * ca + na * cb),
                };
                let (r01, r12) = (fresnel(n0, c0, n1, c1), fresnel(n1, c1, n2, c2));
                for wl in [380.0, 455.5, 532.0, 610.0, 780.0] {
                    let cos2d = (2.0 * 2.0 * std::f64::consts::PI * n1 * h * c1 / wl).cos();
                    let x = 2.0 * r01 * r12 * cos2d;
                    let airy = (r01 * r01 + r12 * r12 + x) / (1.0 + (r01 * r12).powi(2) + x);
                    let film = [Layer {
                        n: n1,
                        thickness_nm: h,
                    }];
                    let (r, _) = stack_rt(n0, &film, n2, t0, wl, pol);
                    assert!(
                        (r - airy).abs() < 1e-12,
                        "n1 {n1} θ {deg}° {pol:?} λ {wl}: TMM {r}, Airy {airy}"
                    );
                }
            }
        }
    }
}

#[test]
fn lossless_stacks_conserve_energy() {
    // Without absorption R + T = 1 (the determinant of every matrix is 1); includes a
    // frustrated-total-reflection gap (n 1.0 between glass at 60°, evanescent inside).
    let glass_gap = [Layer {
        n: 1.0,
        thickness_nm: 150.0,
    }];
    let mixed: Vec<Layer> = (0..17)
        .map(|i| Layer {
            n: 1.3 + 0.07 * (i % 5) as f64,
            thickness_nm: 40.0 + 13.0 * i as f64,
        })
        .collect();
    for pol in POLS {
        for wl in [400.0, 523.0, 650.0, 777.0] {
            for (n0, layers, n_s, deg) in [
                (1.5, &glass_gap[..], 1.5, 60.0f64),
                (1.0, &mixed[..], 1.52, 0.0),
                (1.0, &mixed[..], 1.52, 55.0),
                (1.33, &mixed[..], 1.7, 80.0),
            ] {
                let (r, t) = stack_rt(n0, layers, n_s, deg.to_radians(), wl, pol);
                assert!((0.0..=1.0).contains(&r) && (0.0..=1.0).contains(&t));
                assert!((r + t - 1.0).abs() < 1e-12, "R + T = {}", r + t);
            }
        }
    }
}

#[test]
fn chebyshev_power_equals_repeated_multiplication() {
    // Mⁿ by the Abelès/Chebyshev identity against n explicit products, for a period inside
    // a pass band, inside a stop band and with an evanescent layer.
    let stack = ClusterStack::new(&CrystalConfig {
        n_matrix: 1.2,
        ..CrystalConfig::default()
    })
    .unwrap();
    let cases = [
        (1.0, 650.0),                          // pass band
        (1.0, stack.bragg_wavelength_nm(1.0)), // centre of the stop band
        (0.03, 600.0),                         // low layer evanescent near grazing
    ];
    assert!(
        stack
            .at(1.0)
            .period(cases[1].1, Polarization::S)
            .half_trace()
            .abs()
            > 1.0
    );
    for (cos_theta, wl) in cases {
        for pol in POLS {
            let m = stack.at(cos_theta).period(wl, pol);
            let mut explicit = CharMatrix::IDENTITY;
            for n in 0..=64u32 {
                let closed = m.power(n);
                let scale = [explicit.a, explicit.b, explicit.c, explicit.d]
                    .iter()
                    .fold(1.0f64, |s, v| s.max(v.abs()));
                for (x, y) in [
                    (closed.a, explicit.a),
                    (closed.b, explicit.b),
                    (closed.c, explicit.c),
                    (closed.d, explicit.d),
                ] {
                    assert!(
                        (x - y).abs() < 1e-9 * scale,
                        "n {n}: {closed:?} vs {explicit:?}"
                    );
                }
                explicit = explicit * m;
            }
        }
    }
}

#[test]
fn closed_form_cluster_equals_the_explicit_layer_list() {
    // The cluster's R, T (periodic closed form) against the general stack of 2N layers
    // multiplied out one by one, in the effective medium on both sides.
    let c = CrystalConfig {
        layers: 60,
        n_matrix: 1.3,
        ..CrystalConfig::default()
    };
    let stack = ClusterStack::new(&c).unwrap();
    let h = 0.5 * stack.d111_nm;
    let layers: Vec<Layer> = (0..c.layers)
        .flat_map(|_| {
            [
                Layer {
                    n: stack.n_high,
                    thickness_nm: h,
                },
                Layer {
                    n: stack.n_low,
                    thickness_nm: h,
                },
            ]
        })
        .collect();
    for cos_theta in [1.0f64, 0.8, 0.5, 0.2] {
        let theta = cos_theta.acos();
        for wl in [
            380.0,
            455.0,
            stack.bragg_wavelength_nm(cos_theta),
            585.0,
            700.0,
        ] {
            for pol in POLS {
                let (r, t) = stack.at(cos_theta).rt(wl, pol);
                let (r_ref, t_ref) = stack_rt(stack.n_eff, &layers, stack.n_eff, theta, wl, pol);
                assert!((r - r_ref).abs() < 1e-9 && (t - t_ref).abs() < 1e-9);
            }
        }
    }
}

#[test]
fn periodic_closed_form_handles_deep_stop_bands() {
    // Deep in a stop band of a very long stack U overflows; R must go to 1, not NaN.
    let high = CharMatrix::layer(1.6, 100.0, 640.0, 0.0, Polarization::S);
    let low = CharMatrix::layer(1.2, 133.333, 640.0, 0.0, Polarization::S);
    let m = high * low;
    let (r, t) = periodic_rt(&m, 100_000, 1.4);
    assert_eq!((r, t), (1.0, 0.0));
}

#[test]
fn bragg_peak_follows_snell_corrected_law() {
    // DESIGN §4: λ = 2 d √(n_eff² − sin² θ₀) from air at θ₀. The fine-grid (0.01 nm) peak of
    // the transfer-matrix R must lie within 0.25 % of it (the requirement is 1 %).
    for diameter in [180.0, 250.0, 300.0] {
        let stack = ClusterStack::new(&CrystalConfig {
            sphere_diameter_nm: diameter,
            ..CrystalConfig::default()
        })
        .unwrap();
        for deg in [0.0f64, 20.0, 40.0, 60.0] {
            let theta0 = deg.to_radians();
            let expect = bragg_wavelength_air_nm(stack.d111_nm, stack.n_eff, theta0);
            let cos_in = cos_inside_from_air(stack.n_eff, theta0);
            let (wl, r) = peak(&stack, cos_in, 0.95 * expect, 1.05 * expect, 0.01);
            assert!(
                ((wl - expect) / expect).abs() < 2.5e-3,
                "D {diameter} θ {deg}°: peak {wl:.2} nm (R {r:.3}), Bragg–Snell {expect:.2}"
            );
        }
    }
}

#[test]
fn stop_band_narrows_as_contrast_falls() {
    // DESIGN §4: relative stop band ~5–7 % with air in the voids (synthetic opal), ~1.5 %
    // with water, ~0.3–0.4 % for natural opal's silica cement; it shrinks with contrast.
    let widths: Vec<f64> = [1.0, 1.2, 1.333, 1.42, 1.44]
        .iter()
        .map(|&n_m| relative_stop_band(&ClusterStack::new(&crystal(n_m)).unwrap()))
        .collect();
    assert!(widths.windows(2).all(|w| w[0] > w[1]), "{widths:?}");
    assert!((0.05..=0.07).contains(&widths[0]), "air {:.4}", widths[0]);
    assert!(
        (0.012..=0.018).contains(&widths[2]),
        "water {:.4}",
        widths[2]
    );
    let natural = relative_stop_band(&ClusterStack::new(&CrystalConfig::default()).unwrap());
    assert!(
        (0.003..=0.004).contains(&natural),
        "natural opal {natural:.5}"
    );
}

#[test]
fn stop_band_matches_the_fourier_coupling_and_not_a_quarter_wave_pair() {
    // Coupled-wave theory (Yariv & Yeh, Optical Waves in Crystals §6.5): a permittivity
    // modulation with first Fourier coefficient ε₁ opens a gap Δλ/λ = ε₁/ε̄. A full-contrast
    // quarter-wave pair of sphere and matrix material has Δλ/λ = (4/π) asin(|n_s − n_m| /
    // (n_s + n_m)) (Macleod §5.2) and overstates the crystal's gap about fourfold.
    let c = CrystalConfig::default();
    let stack = ClusterStack::new(&c).unwrap();
    let gap = relative_stop_band(&stack);
    let coupled = stack.relative_gap();
    assert!(
        ((gap - coupled) / coupled).abs() < 0.02,
        "TMM {gap}, coupled-wave {coupled}"
    );
    let quarter_wave =
        4.0 / std::f64::consts::PI * ((c.n_sphere - c.n_matrix) / (c.n_sphere + c.n_matrix)).asin();
    let ratio = quarter_wave / gap;
    assert!(
        (3.0..=4.5).contains(&ratio),
        "quarter-wave / FCC = {ratio:.2}"
    );
}

#[test]
fn peak_grows_with_layers_as_coupled_wave_theory_says() {
    // Kogelnik (1969) / Yariv & Yeh §6.5: a weak grating of N periods reflects
    // R = tanh²(κL) at the Bragg wavelength, κL = (π/2) N ε₁/ε̄.
    let mut last = 0.0;
    for layers in [25, 50, 100, 200, 400, 800] {
        let stack = ClusterStack::new(&CrystalConfig {
            layers,
            ..CrystalConfig::default()
        })
        .unwrap();
        let lambda = stack.bragg_wavelength_nm(1.0);
        let (_, r) = peak(&stack, 1.0, lambda - 5.0, lambda + 5.0, 0.005);
        let kl = 0.5 * std::f64::consts::PI * f64::from(layers) * stack.relative_gap();
        let expect = kl.tanh().powi(2);
        assert!(
            (r - expect).abs() < 0.01,
            "N {layers}: R {r:.4}, tanh² {expect:.4}"
        );
        assert!(r > last, "N {layers}: R {r} not above {last}");
        last = r;
    }
}
