#!/usr/bin/env python3
"""Writes cases.txt, the bad-input corpus run by tests/cli_bad_inputs.rs.

One case a line: `exit | env | args | file | expected`, where env is `-` or `K=V,K=V`,
args are split on spaces (`''` is an empty argument), file is `-` or `NAME:TEXT` (TEXT with
`\\n` escapes; written beside the fixtures) and expected is a substring of the one error line.
Edit the lists below and run `python3 generate.py > cases.txt`; hand-written lines may also
be appended to cases.txt directly.
"""

cases = []


def case(args, expected, env="-", file="-", code=2):
    cases.append(f"{code} | {env} | {args} | {file} | {expected}")


TINY = "--width 8 --height 6 --rays 64"

look = {
    "--width": ["0", "-1", "16385", "99999999999", "abc", "1.5", "''"],
    "--height": ["0", "-1", "16385", "4294967296", "x"],
    "--diameter": ["-1", "0", "49", "2001", "nan", "inf", "abc"],
    "--bins": ["0", "-1", "1001", "abc"],
    "--rays": ["0", "-1", "abc", "1000000001", "1e3"],
    "--cutoff": ["0", "1e-7", "0.8", "nan", "-1"],
    "--body-tone": ["0", "10", "-1", "256"],
    "--exposure": ["21", "-21", "nan", "inf"],
    "--spp": ["0", "-1", "65537", "x"],
    "--tilt": ["90", "-90", "nan", "x"],
}
for sub in ["render", "sweep", "bench"]:
    for flag, values in look.items():
        for v in values:
            case(f"{sub} {flag} {v}", flag)

for v in ["90", "-90", "nan", "1e308", "abc"]:
    case(f"render --light-angle {v}", "--light-angle")

for sub in ["render", "sweep"]:
    for v in ["0", "-1", "nan", "inf", "1e9", "abc"]:
        case(f"{sub} --preset harlequin --time-limit {v} {TINY}", "--time-limit")
# --time-limit bounds every stage, the stone's preparation included: a stone of about
# 240 000 grains takes seconds to grow whatever the method.
SLOW = 'slow.toml:[domains]\\npattern = "grains"\\ngrain_size_mm = 0.24\\n'
for method in ["lobe", "path", "stored"]:
    case(f"render slow.toml --method {method} --time-limit 0.05 {TINY}",
         "--time-limit 0.05: the limit passed during the stone's preparation", file=SLOW)
    case(f"sweep slow.toml --method {method} --frames 2 --time-limit 0.05 {TINY}",
         "--time-limit 0.05: the limit passed during the stone's preparation", file=SLOW)

for flag, v in [("--from", "90"), ("--from", "nan"), ("--to", "-90"), ("--to", "inf"),
                ("--light-from", "90"), ("--light-to", "x")]:
    case(f"sweep --preset paper {flag} {v} {TINY}", flag)
for flag, v in [("--tilt-from", "90"), ("--tilt-to", "nan"), ("--turn-from", "361"),
                ("--turn-to", "-inf"), ("--env-from", "400"), ("--env-to", "abc")]:
    case(f"sweep {flag} {v} {TINY}", flag)
# What moves nothing in the scene is refused, naming what would.
case(f"sweep --light-from -45 {TINY}", "no light")
case(f"sweep --from -45 --to 45 {TINY}", "no light")
case(f"render --light-angle 20 {TINY}", "no light")
case(f"sweep --preset paper --env-from 0 {TINY}", "no environment")
case(f"sweep --tilt-from -10 --turn-to 10 {TINY}", "moves one thing")
case(f"sweep --tilt 5 --tilt-from -10 {TINY}", "--tilt")
case(f"scene --from nosuch.png", "--from nosuch.png")
case(f"scene --from keep.png", "not a readable PNG")
for flag, v in [("--frames", "0"), ("--frames", "1001"), ("--frames", "-1"), ("--frames", "x"),
                ("--columns", "0"), ("--columns", "100"), ("--delay-ms", "70000"),
                ("--delay-ms", "-5"), ("--sheet", "x.jpg"), ("--animation", "x.mp4"),
                ("--video", "x.avi"), ("--video", "x.gif"), ("--video", "nodir/v.mp4"),
                ("--frames-dir", "afile"), ("--sheet", "keep.png/"), ("--sheet", "nodir/s.png"),
                ("--animation", "adir.json"), ("--stats", "adir.json")]:
    case(f"sweep {flag} {v} {TINY}", flag)
case(f"sweep --resume {TINY}", "--frames-dir")
case(f"sweep --frames-dir fresh --resume {TINY}", "--resume")

for flag, v in [("--slice-z", "25"), ("--slice-z", "-1"), ("--scale", "0"), ("--scale", "65"),
                ("--scale", "-1"), ("--output", "x.jpg"), ("--stats", "x.txt"),
                ("--output", "/proc/m.png"), ("--output", "afile/m.png"), ("--stats", "adir.json"),
                ("--seed", "-1"), ("--seed", "9223372036854775808"), ("--preset", "nosuch")]:
    case(f"structure {flag} {v}", flag if flag not in ("--preset",) else "nosuch")

for flag, v in [("--diameter", "10"), ("--diameter", "nan"), ("--n-sphere", "0.5"),
                ("--n-matrix", "5"), ("--layers", "0"), ("--layers", "100001"),
                ("--layers", "-1"), ("--angles", "90"), ("--angles", "nan"),
                ("--angles", "abc"), ("--angles", "0,95"), ("--from-nm", "0"),
                ("--from-nm", "-5"), ("--to-nm", "100"), ("--step-nm", "0"),
                ("--step-nm", "-1"), ("--step-nm", "1e-9"), ("--output", "x.txt"),
                ("--plot", "x.jpg"), ("--output", "afile/x.csv"), ("--plot", "nodir/p.png")]:
    case(f"spectrum {flag} {v}", flag)

for flag, v in [("--output", "keep.png/"), ("--output", "nodir/x.png"), ("--output", "/proc/x.png"),
                ("--output", "/sys/x.png"), ("--output", "x.tiff"), ("--output", "afile/x.png"),
                ("--output", "sub"), ("--spectral", "x.png"), ("--spectral", "afile/x.exr"),
                ("--stats", "adir.json"), ("--stats", "x.csv"), ("--stats", "nodir/s.json"),
                ("--spectral", "keep.exr"), ("--output", "''")]:
    extra = " --output keep.exr" if v == "keep.exr" else ""
    case(f"render {flag} {v}{extra} {TINY}", flag if v != "keep.exr" else "the same file")

csvs = {
    "empty": ("", "found 0 data rows"),
    "one": ("400,1\\n", "found 1 data rows"),
    "desc": ("500,1\\n400,1\\n", "does not increase"),
    "dup": ("400,1\\n400,2\\n", "does not increase"),
    "nan": ("400,1\\n500,nan\\n", "not a finite number"),
    "inf": ("400,1\\n500,inf\\n", "not a finite number"),
    "text": ("400,1\\n500,abc\\n", "value `abc`"),
    "three": ("400,1,2\\n500,1\\n", "expected 2"),
    "onefield": ("400\\n500\\n", "expected 2"),
    "neg": ("-5,1\\n400,1\\n", "must be positive"),
    "zero": ("0,1\\n400,1\\n", "must be positive"),
    "huge": ("400,1e308\\n500,1e308\\n", "too large to integrate"),
    "hugewl": ("1e308,1\\n1.5e308,1\\n", "outside the 360–830 nm"),
    "infrared": ("900,1\\n1000,1\\n", "outside the 360–830 nm"),
    "semicolon": ("400;1\\n500;1\\n", "expected 2"),
    "badwl": ("400,1\\nx,1\\n", "wavelength `x`"),
}
for name, (text, expected) in csvs.items():
    case("color s.csv", expected, file=f"s.csv:{text}")
    if name in ("nan", "desc", "huge", "three"):
        case("color s.csv --reflectance", expected, file=f"s.csv:{text}")
case("color missing.csv", "missing.csv")
case("color sub", "is a directory")
case("color /dev/zero", "larger than the limit")
case("color s.csv --illuminant a", "--illuminant", file="s.csv:400,1\\n500,1\\n")
case("color s.csv --reflectance --illuminant z", "--illuminant", file="s.csv:400,1\\n500,1\\n")
case("color s.csv", "not UTF-8", file="s.csv:400,1\\n\\xff500,1\\n")

scenes = [
    ("[structure]\\nvoid_ratoi = 0.3", "structure.void_ratoi"),
    ("[structure]\\nvoid_ratio = 1.5", "structure.void_ratio"),
    ("[structure]\\nvoid_ratio = 0.0", "structure.void_ratio"),
    ("[structure]\\nvoid_ratio = nan", "structure.void_ratio"),
    ("[structure]\\nvoid_ratio = inf", "structure.void_ratio"),
    ("[structure]\\nvoid_ratio = \"a\"", "structure.void_ratio"),
    ("[structure]\\ngrid = [100, 0, 25]", "structure.grid"),
    ("[structure]\\ngrid = [1, 2, 3, 4]", "structure.grid"),
    ("[structure]\\ngrid = [1, 2]", "structure.grid"),
    ("[structure]\\ngrid = []", "structure.grid"),
    ("[structure]\\ngrid = [-1, 2, 3]", "structure.grid"),
    ("[structure]\\ngrid = [1.5, 2, 3]", "structure.grid"),
    ("[structure]\\ngrid = 5", "structure.grid"),
    ("[structure]\\ngrid = [100000, 100000, 100000]", "structure.grid"),
    ("[structure]\\nsemi_axes_mm = [1.0, 2.0, 3.0, 4.0]", "structure.semi_axes_mm"),
    ("[structure]\\nsemi_axes_mm = [10.0, -1.0, 2.0]", "structure.semi_axes_mm"),
    ("[structure]\\nsemi_axes_mm = [10.0, nan, 2.0]", "structure.semi_axes_mm"),
    ("[structure]\\nsemi_axes_mm = [1e9, 1.0, 2.0]", "structure.semi_axes_mm"),
    ("[structure]\\nmean_radius_cells = -6.0", "structure.mean_radius_cells"),
    ("[structure]\\nmean_radius_cells = 0", "structure.mean_radius_cells"),
    ("[structure]\\nseed = -1", "structure.seed"),
    ("[structure]\\nseed = 99999999999999999999", "structure.seed"),
    ("[structure]\\norientation_jitter_deg = 181", "structure.orientation_jitter_deg"),
    ("structure = [[1, 2, 3], [1.0, 1.0, 1.0]]", "field `structure`"),
    ("render = [640, 480]", "field `render`"),
    ("light = 5", "field `light`"),
    ("crystal = \"opal\"", "field `crystal`"),
    ("[crystal]\\nsphere_diameter_nm = -250.0", "crystal.sphere_diameter_nm"),
    ("[crystal]\\nsphere_diameter_nm = 1e400", "crystal.sphere_diameter_nm"),
    ("[crystal]\\nn_sphere = 0.9", "crystal.n_sphere"),
    ("[crystal]\\nn_matrix = 4.5", "crystal.n_matrix"),
    ("[crystal]\\nfilling_fraction = 1.0", "crystal.filling_fraction"),
    ("[crystal]\\nfilling_fraction = nan", "crystal.filling_fraction"),
    ("[crystal]\\nlayers = 0", "crystal.layers"),
    ("[crystal]\\nlayers = 4294967296", "crystal.layers"),
    ("[crystal]\\nlayers = -3", "crystal.layers"),
    ("[crystal]\\ndiffuse_fraction = 1.0", "crystal.diffuse_fraction"),
    ("[crystal]\\nangles = 89", "crystal.angles"),
    ("[crystal]\\nangles = 10001", "crystal.angles"),
    ("[spectrum]\\nbins = 0", "spectrum.bins"),
    ("[spectrum]\\nbins = 1001", "spectrum.bins"),
    ("[spectrum]\\nmin_nm = 100", "spectrum.min_nm"),
    ("[spectrum]\\nmax_nm = 300", "spectrum.max_nm"),
    ("[spectrum]\\nmax_nm = 5000", "spectrum.max_nm"),
    ("[light]\\nangle_deg = 120.0", "light.angle_deg"),
    ("[light]\\ncutoff = 0.0", "light.cutoff"),
    ("[light]\\ncutoff = 0.8", "light.cutoff"),
    ("[light]\\nrays = 0", "light.rays"),
    ("[light]\\nrays = -5", "light.rays"),
    ("[light]\\nrays = 99999999999999999999", "light.rays"),
    ("[light]\\nintensity = 0", "light.intensity"),
    ("[light]\\nintensity = 1e7", "light.intensity"),
    ("[light]\\ndistance_mm = -1", "light.distance_mm"),
    ("[light]\\nkind = \"laser\"", "light.kind"),
    ("[light]\\nilluminant = \"x\"", "light.illuminant"),
    ("[light]\\nroulette = 1", "light.roulette"),
    ("[camera]\\nfov_deg = 0", "camera.fov_deg"),
    ("[camera]\\nfov_deg = 171", "camera.fov_deg"),
    ("[camera]\\ntilt_deg = 90", "camera.tilt_deg"),
    ("[camera]\\ndistance_mm = nan", "camera.distance_mm"),
    ("[render]\\nwidth = 0", "render.width"),
    ("[render]\\nwidth = 99999999999", "render.width"),
    ("[render]\\nwidth = 99999999999999999999", "render.width"),
    ("[render]\\nwidth = -5", "render.width"),
    ("[render]\\nwidth = 16384\\nheight = 16384", "render.width"),
    ("[render]\\nbody_tone = 12", "render.body_tone"),
    ("[render]\\nbody_tone = 256", "render.body_tone"),
    ("[render]\\nphong_exponent = -1", "render.phong_exponent"),
    ("[render]\\ngloss = 11", "render.gloss"),
    ("[render]\\nbackground = 2", "render.background"),
    ("[render]\\nreflection_block = 0", "render.reflection_block"),
    ("[render]\\nreflection_block = 9", "render.reflection_block"),
    ("[color]\\nexposure_ev = 30", "color.exposure_ev"),
    ("[color]\\nbit_depth = 12", "color.bit_depth"),
    ("[color]\\nspace = \"cmyk\"", "color.space"),
    ("[color]\\ngamut = \"x\"", "color.gamut"),
    ("[nosuch]\\na = 1", "nosuch"),
    ("[structure\\n", "line"),
    ("[structure]\\nvoid_ratio = 0.2\\nvoid_ratio = 0.3", "void_ratio"),
    ("[structure]\\n[structure]", "structure"),
    ("= 5", "line"),
    ("\\\"unterminated = 1", "line"),
    ("[render]\\nwidth = 0x", "line"),
]
for text, expected in scenes:
    case("render s.toml", expected, file=f"s.toml:{text}")
for text, expected in scenes[::4]:
    case("scene s.toml", expected, file=f"s.toml:{text}")
    case("structure s.toml", expected, file=f"s.toml:{text}")
case("render missing.toml", "missing.toml")
case("render sub", "is a directory")
case("render /dev/zero", "larger than the limit")
case("scene s.toml", "not UTF-8", file="s.toml:[render]\\nwidth = 8 \\xff\\n")
case("render s.toml --preset paper", "--preset", file="s.toml:")

envs = [
    ("RAYON_NUM_THREADS=0", "RAYON_NUM_THREADS"),
    ("RAYON_NUM_THREADS=-1", "RAYON_NUM_THREADS"),
    ("RAYON_NUM_THREADS=abc", "RAYON_NUM_THREADS"),
    ("RAYON_NUM_THREADS=5000", "RAYON_NUM_THREADS"),
    ("RAYON_NUM_THREADS=", "RAYON_NUM_THREADS"),
    ("RAYON_NUM_THREADS=2.5", "RAYON_NUM_THREADS"),
    ("OPALRAY_SIMD=fast", "OPALRAY_SIMD"),
    ("OPALRAY_SIMD=AVX512", "OPALRAY_SIMD"),
    ("OPALRAY_SIMD=", "OPALRAY_SIMD"),
    ("OPALRAY_MAX_MEMORY_MB=1", "OPALRAY_MAX_MEMORY_MB"),
    ("OPALRAY_MAX_MEMORY_MB=abc", "OPALRAY_MAX_MEMORY_MB"),
]
for env, expected in envs:
    for sub in ["scene", f"render {TINY}"]:
        if "MEMORY" in env and sub == "scene":
            continue
        case(sub, expected, env=env)

# Hand-written after the first round (issue 22), kept here so the file regenerates whole.
for section, expected in [("[environment]\\nkind = \"studio\"", "environment.kind"),
                          ("[light]\\nkind = \"rect\"", "light.kind"),
                          ("cell_mm = 0.01", "integrator.cell_mm")]:
    case("render s.toml", expected,
         file=f"s.toml:[integrator]\\nmethod = \"stored\"\\n{section}")

# Issue 45: each method's [integrator] fields its own; another method's is refused by name.
for section, expected in [("method = \"path\"\\ncell_mm = 0.2", "integrator.cell_mm"),
                          ("method = \"lobe\"\\nmax_depth = 8", "integrator.max_depth"),
                          ("spp = 4", "integrator.spp"),
                          ("method = \"stored\"\\ndenoise = true", "integrator.denoise")]:
    case(f"render s.toml {TINY}", expected, file=f"s.toml:[integrator]\\n{section}")
case("render --preset black-opal --denoise --width 8 --height 6", "--denoise")

# Issue 44: environment maps. A path-traced scene reading m.hdr (or m.exr) beside it.
ENV_SCENE = "e.toml:[integrator]\\nmethod = \"path\"\\n[environment]\\nkind = \"file\"\\npath = \"{}\""
ENV_RUN = "render e.toml --width 8 --height 6 --spp 1"
PIXEL = "\\x80\\x80\\x80\\x81"


def env_case(map_name, body, expected, env="-"):
    case(ENV_RUN, expected, env=env,
         file=ENV_SCENE.format(map_name) + f" & {map_name}:{body}")


for resolution in ["-Y 4294967296 +X 4294967296", "-Y 3 +X 6148914691236517206",
                   "-Y 18446744073709551615 +X 2", "-Y 2 +X 16384", "-Y 16384 +X 2",
                   "-Y 99999999999999999999 +X 2"]:
    expected = "unreadable resolution" if "9999999999" in resolution else "more than the limit"
    env_case("m.hdr", f"#?RADIANCE\\n\\n{resolution}\\n{PIXEL}", expected)
for factors in ["EXPOSURE=1e-30\\nEXPOSURE=1e-30", "EXPOSURE=1e30\\nEXPOSURE=1e30",
                "EXPOSURE=1e20\\nEXPOSURE=1e20", "EXPOSURE=0", "EXPOSURE=-1",
                "EXPOSURE=nan", "EXPOSURE=inf"]:
    env_case("m.hdr", f"#?RADIANCE\\n{factors}\\n\\n-Y 2 +X 4\\n{PIXEL * 8}", "EXPOSURE")
env_case("m.hdr", "#?RADIANCE\\n\\n-Y 2 +X 4\\n" + "\\x00" * 32, "black")
env_case("m.hdr", "@fifo", "not a regular file")
env_case("m.exr", "@fifo", "not a regular file")
env_case("m.exr", "not an OpenEXR file", "environment.path")
env_case("m.hdr", "#?RADIANCE\\n\\n-Y 4096 +X 8192\\n", "environment map",
         env="OPALRAY_MAX_MEMORY_MB=200")
env_case("m.hdr", "#?RADIANCE\\n\\n-Y 2 +X 4\\n", "ends early")

# Every array field checks its length.
for field, values in [("[domains]\\nstretch", ["[1.0, 2.0, 3.0, 4.0]", "[1.0, 2.0]", "[]"]),
                      ("[light]\\nsize_mm", ["[10.0, 20.0, 30.0]", "[10.0]", "[]"]),
                      ("[structure]\\ngrid", ["[10, 10]"]),
                      ("[structure]\\nsemi_axes_mm", ["[1.0, 2.0]"])]:
    name = field.replace("[", "").replace("]\\n", ".")
    for v in values:
        case(f"render s.toml {TINY}", name, file=f"s.toml:{field} = {v}")

# The frames folder is an output like the others, and a folder not ours is refused.
for outputs, folder in [("--sheet keep.png --animation a.gif", "a.gif"),
                        ("--sheet keep.png --stats s.json", "s.json"),
                        ("--sheet s.png", "s.png"),
                        ("--sheet keep.png", "."),
                        ("--sheet sub/s.png", "sub")]:
    case(f"sweep {outputs} --frames-dir {folder} {TINY}", "--frames-dir")
for files in ["u/frame-0000.png:mine & u/sweep.json:{\"mine\": 1}",
              "u/frame-0000.png:mine",
              "u/notes.txt:mine",
              "u/sweep.json:not json",
              "u/sweep.json:@fifo"]:
    case(f"sweep --sheet keep.png --frames-dir u {TINY}", "--frames-dir", file=files)
    case(f"sweep --sheet keep.png --frames-dir u --resume {TINY}", "--frames-dir", file=files)

# Messages: flags typed with a word processor's dashes, mistyped flags keep clap's tip.
for sub in ["render", "sweep", "bench"]:
    for dash in ["\u2014", "\u2013", "\u2010"]:
        case(f"{sub} {dash}width 64", "--width")
    case(f"{sub} --widht 64", "similar argument exists")
case("render --light-angle \u221230", "-30")
case("sweep --from \u221260", "-60")

# Every field of the complete scene (`opalray scene`, 2026-12-06) with values of the wrong
# type, out of range, not finite and of the wrong shape: refused naming the field.
COMPLETE_SCENE = """
[structure]
grid = [100, 75, 25]
semi_axes_mm = [10.0, 7.5, 2.5]
mean_radius_cells = 6.0
void_ratio = 0.2
seed = 4
orientation_jitter_deg = 0.0
[crystal]
sphere_diameter_nm = 235.0
n_sphere = 1.45
n_matrix = 1.42
filling_fraction = 0.74
layers = 400
diffuse_fraction = 0.0
angles = 181
[spectrum]
min_nm = 380.0
max_nm = 780.0
bins = 40
[light]
kind = "none"
angle_deg = 30.0
illuminant = "D65"
intensity = 1.0
distance_mm = 100.0
radius_mm = 10.0
size_mm = [100.0, 100.0]
rays = 65536
cutoff = 0.02
roulette = false
[camera]
distance_mm = 100.0
fov_deg = 13.5
tilt_deg = -10.0
turn_deg = 0.0
[render]
width = 640
height = 480
phong_exponent = 40.0
body_tone = 1
gloss = 1.0
background = 0.005
reflection_block = 2
[color]
space = "srgb"
gamut = "hue-preserving"
exposure_ev = 0.0
bit_depth = 8
[domains]
pattern = "grains"
grain_size_mm = 2.0
grain_size_spread = 0.3
stretch = [2.5, 2.5, 0.12]
orientation = "settled"
correlation_mm = 6.0
orientation_spread_deg = 20.0
void_fraction = 0.05
sphere_diameter_spread = 0.12
diameter_correlation_mm = 2.5
tilt_correlation_mm = 0.0
tilt_jitter_deg = 5.0
mosaic_spread_deg = 1.5
families = "all"
boundary_roughness = 0.4
[body]
cut = "cabochon"
dome_height_mm = 4.0
back_height_mm = 0.0
colour_bar_mm = 2.0
slice_mm = 1.0
backing = "black"
cap_index = 1.544
potch_extinction_per_mm = 3.0
anisotropy = 0.4
domain_haze = 0.0
[environment]
kind = "studio"
path = ""
intensity = 11.0
rotation_deg = 0.0
[integrator]
method = "lobe"
spp = 4
max_depth = 8
wavelengths = 4
seed = 0
cell_mm = 0.15
denoise = false
"""


def bad_values(default):
    """Values no field with this default accepts."""
    if default.startswith("["):
        n = default.count(",") + 1
        values = ["[]", "[" + ", ".join(["1.0"] * (n + 1)) + "]", '"x"',
                  '["a"' + ", 1.0" * (n - 1) + "]"]
        return values + (["[1.0]"] if n > 1 else [])
    if default.startswith('"'):
        return ['"nosuch"', "1", '["a"]']
    if default in ("true", "false"):
        return ['"x"', "1"]
    if "." in default or "e" in default:
        return ["nan", "inf", "-inf", "1e300", "-1e300", '"x"', "[1.0]"]
    return ["-1", '"x"', "1.5", "[1]", "9223372036854775807"]


section = None
for line in COMPLETE_SCENE.strip().splitlines():
    if line.startswith("["):
        section = line.strip("[]")
        continue
    key, default = (x.strip() for x in line.split("=", 1))
    for v in bad_values(default):
        if key == "seed" and v == "9223372036854775807":
            continue  # the seeds take every 64-bit value
        case(f"render s.toml {TINY}", f"{section}.{key}", file=f"s.toml:[{section}]\\n{key} = {v}")

for line in cases:
    print(line)
