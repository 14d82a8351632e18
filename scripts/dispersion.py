#!/usr/bin/env python3
"""What silica's dispersion does to opal's lines and to the surface, from the law alone.

    scripts/dispersion.py [--n-sphere 1.45] [--n-matrix 1.42] [--filling 0.74]

Fused silica's Sellmeier law (Malitson 1965, J. Opt. Soc. Am. 55, 1205) shifted to the
scene's indices at 589.3 nm, for the spheres and the cement alike (docs/model.md, silica's
dispersion). Prints, for sphere diameters 150-350 nm, the face-on (111) line without and with
the dispersion (the fixed point λ = 2 d n̄(λ)), the shift, the coupling's change and the group
ratio k = 1 − λ n̄'/n̄ at the line; then the refraction at the stone's surface at 45° from air
for 450 and 650 nm (the "fire" the renderers leave out). Needs only Python 3.
"""
import math
import sys

B = (0.6961663, 0.4079426, 0.8974794)
C = (0.0684043**2, 0.1162414**2, 9.896161**2)


def silica(nm):
    l2 = (nm * 1e-3) ** 2
    return math.sqrt(1.0 + sum(b * l2 / (l2 - c) for b, c in zip(B, C)))


def main(argv):
    args = dict(zip(argv[1::2], argv[2::2]))
    n_s = float(args.get("--n-sphere", 1.45))
    n_m = float(args.get("--n-matrix", 1.42))
    f = float(args.get("--filling", 0.74))

    def indices(nm):
        shift = silica(nm) - silica(589.3)
        return n_s + shift, n_m + shift

    def n_eff(nm):
        a, b = indices(nm)
        return math.sqrt(f * a * a + (1 - f) * b * b)

    def contrast(nm):
        a, b = indices(nm)
        return (a * a - b * b) / n_eff(nm) ** 2

    n_d = n_eff(589.3)
    print(f"n_sphere {n_s}, n_matrix {n_m} at 589.3 nm; n_eff {n_d:.5f}")
    print("D nm   constant nm  silica nm  shift nm  coupling  group k")
    for d in (150, 200, 235, 250, 270, 300, 350):
        x = 2 * d * math.sqrt(2 / 3) * n_d
        lam = x
        for _ in range(30):
            lam = x * n_eff(lam) / n_d
        h = 1e-3
        slope = (n_eff(lam + h) - n_eff(lam - h)) / (2 * h)
        k = 1 - lam * slope / n_eff(lam)
        scale = contrast(lam) / contrast(589.3)
        print(f"{d:5d}  {x:10.2f}  {lam:9.2f}  {lam - x:+8.2f}  {scale:8.4f}  {k:7.4f}")
    inside = {nm: math.degrees(math.asin(math.sin(math.radians(45)) / n_eff(nm))) for nm in (450, 650)}
    print(
        f"45° from air: refracted to {inside[450]:.3f}° at 450 nm, {inside[650]:.3f}° at 650 nm "
        f"(n_eff {n_eff(450):.5f}, {n_eff(650):.5f}): spread {inside[650] - inside[450]:.3f}° inside"
    )
    # Out again through a face tilted by 20° from the entry face: the exit angles differ.
    tilt = math.radians(20)
    out = {}
    for nm in (450, 650):
        t = math.radians(inside[nm]) - tilt
        out[nm] = math.degrees(math.asin(min(1.0, n_eff(nm) * math.sin(t))))
    print(
        f"out through a face 20° from the entry face: {out[450]:.3f}° and {out[650]:.3f}°: "
        f"spread {abs(out[450] - out[650]):.3f}° in air"
    )


if __name__ == "__main__":
    main(sys.argv)
