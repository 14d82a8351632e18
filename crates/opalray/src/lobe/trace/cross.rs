//! The eye ray crossing a domain: every line's reflection of the lights, walked out where
//! it can add light ([`Tracer::reflected`]'s cull), and the notches it carries on.

use super::*;

impl Tracer<'_> {
    /// The eye ray along `ray` crossing `domain` over `span`, with weight `w`: every line's
    /// reflection of the lights, then its notch on the way on.
    pub(super) fn cross(&mut self, ray: &Ray, span: Span, domain: u32, w: f32, sums: &mut Sums) {
        let stone = self.stone;
        let dir = ray.direction;
        let mut lines = std::mem::take(&mut self.lines);
        lines.clear();
        stone.lines(domain, dir, span.t1 - span.t0, &mut lines);
        let face = ray.at(span.t0);
        // Reflections are read back keyed by the eye ray's segment and the domain's
        // crossing along it (`reuse`).
        let reusable = self.reuse.on();
        let crossing = if reusable {
            self.crossing_of(domain)
        } else {
            0
        };
        let mut colours = std::mem::take(&mut self.line_colours);
        colours.clear();
        for l in &lines {
            // `tanh ν` of each polarisation once, for the profile, the band and the notch.
            let tanh = (l.line.nu_s.tanh(), l.line.nu_p.tanh());
            let profile = LineProfile::of_tanh(&l.line, tanh);
            let (xyz, s) = self.colours.of_profile(&profile);
            let cos_theta = -dir.dot(l.normal);
            let sigma = stone.lobe_sigma(l.kind, cos_theta);
            let band = Band::of_tanh(&l.line, tanh, cos_theta.into(), sigma.into());
            let t_in = self.eye_passes(&band);
            colours.push(CrossedLine {
                xyz,
                s,
                notch: Band::notch_tanh(&l.line, tanh),
            });
            let weight = w * t_in as f32;
            if weight * xyz[1] as f32 * (self.peak + self.body_peak) > CUT {
                // The line as the lobe's normals spread it.
                let (xyz, s, center) = self.colours.in_lobe(
                    &l.line,
                    (xyz, s),
                    &profile,
                    cos_theta.into(),
                    sigma.into(),
                );
                let vivid = weight * xyz.iter().fold(0.0f64, |a, &b| a.max(b)) as f32;
                let meeting = Meeting {
                    segment: self.segment,
                    way: dir,
                    domain,
                    crossing,
                    slot: l.slot,
                    luminance: weight * xyz[1] as f32,
                    vivid,
                };
                let read = reusable.then(|| self.reuse.find(&meeting)).flatten();
                let seen = match read {
                    Some(seen) => seen,
                    None => {
                        let out = Out {
                            face,
                            dir: reflect(dir, l.normal),
                            domain,
                            hint: span.hint,
                            band,
                        };
                        let (seen, thorough) =
                            self.reflected(&out, &l.line, sigma, meeting.luminance, vivid);
                        if reusable {
                            self.reuse.keep(&meeting, seen, thorough);
                        }
                        seen
                    }
                };
                self.add_line(f64::from(weight * seen), xyz, s, center, sums);
            }
            if self.setup.light.is_some() {
                self.light_at(ray.at(span.t0 + EPSILON_MM), dir, domain, l, weight, sums);
            }
        }
        self.carry_notches(&lines, &colours);
        self.line_colours = colours;
        self.lines = lines;
    }

    /// The eye ray goes on through a crossing's `lines` (as [`Tracer::cross`] found them,
    /// `crossed`), carrying each line's notch on the broadband light: what the earlier lines,
    /// this crossing's before it among them, leave of it, each read over the notch itself
    /// (the light goes through the line at the family's normal, unspread).
    fn carry_notches(&mut self, lines: &[ActiveLine], crossed: &[CrossedLine]) {
        for (k, (l, c)) in lines.iter().zip(crossed).enumerate() {
            if self.eye_lines.len() >= MAX_EYE_LINES {
                break;
            }
            let (xyz, s) = (c.xyz, c.s);
            let mut t_prev = self.eye_passes(&c.notch);
            for before in &crossed[..k] {
                t_prev *= 1.0 - c.notch.taken_by(&before.notch);
            }
            for (n, v) in self.notch_xyz.iter_mut().zip(xyz) {
                *n += t_prev * v;
            }
            if let Some(b) = self.setup.spectral.grid.bin_of(l.line.center_nm) {
                self.notch_bins[b] += (t_prev * s / self.bin_width_nm) as f32;
            }
            self.eye_windows.push(l.line.window_nm());
            self.eye_bands.push(c.notch);
            self.eye_lines.push(l.line);
        }
    }

    /// What the lines the eye ray has crossed leave of the light of a line of band `band`:
    /// `Π (1 − share)`, each notch read over the band ([`Band::taken_by`]).
    fn eye_passes(&self, band: &Band) -> f64 {
        self.eye_bands
            .iter()
            .fold(1.0, |t, notch| t * (1.0 - band.taken_by(notch)))
    }

    /// `Π (1 − R)` at `wavelength_nm` of the lines the eye ray has crossed.
    pub(super) fn eye_transmittance(&self, wavelength_nm: f64) -> f64 {
        let mut t = 1.0;
        for (k, (lo, hi)) in self.eye_windows.iter().enumerate() {
            if wavelength_nm > *lo && wavelength_nm < *hi {
                t *= 1.0 - self.eye_lines[k].reflectance(wavelength_nm);
            }
        }
        t
    }

    /// The radiance (in the stone, relative to the light's) that reaches the domain's face
    /// `face` against `dir`, the mirror direction of `line` whose lobe has width `sigma`
    /// (over normals, radians): the environment through the lobe, carried in through every
    /// surface event up to [`MAX_SEGMENTS`], notched by the lines on the way (each read over
    /// the reflection's band) and dimmed by the potch and haze. Where `weight` times the line's luminance
    /// times what the surface alone lets through is under [`CUT`], 0: the walks through the
    /// domains, which only dim it, are then left out — unless the dome traps it and `vivid`,
    /// its colour's largest tristimulus value times the eye ray's weight, is large enough
    /// for its second reflections to be walked ([`Tracer::trapped`]). Whether it was walked
    /// through the domains, beside.
    pub(super) fn reflected(
        &mut self,
        out: &Out,
        line: &BraggLine,
        sigma: f32,
        weight: f32,
        vivid: f32,
    ) -> (f32, bool) {
        if self.reaches_cut(out.face, out.dir, sigma, weight) || self.trapped(out, vivid) {
            (
                self.follow_out(out, line.center_nm, sigma, true, vivid),
                true,
            )
        } else if weight * self.body_peak >= BODY_CUT {
            // Only the body can add enough: its light along the way, the lines not read.
            (
                self.follow_out(out, line.center_nm, sigma, false, vivid),
                false,
            )
        } else {
            (0.0, false)
        }
    }

    /// How many times the eye ray crossed `domain` on the segment at hand before now (and
    /// this crossing counted).
    fn crossing_of(&mut self, domain: u32) -> u8 {
        let key = (self.segment, domain);
        let before = self.crossed.iter().filter(|&&d| d == key).count();
        self.crossed.push(key);
        before.min(u8::MAX as usize) as u8
    }
}
