use super::*;

/// A square `size` wide in the plane y = `y`, cut into `n` x `n` cells of two
/// triangles, facing `+y` (`up`) or `-y`.
fn square(y: f32, size: f32, n: usize, up: bool, rho: f32, e: f32) -> Vec<Patch> {
    let mut out = Vec::new();
    let h = size / n as f32;
    for j in 0..n {
        for i in 0..n {
            let (x0, z0) = (-size / 2.0 + i as f32 * h, -size / 2.0 + j as f32 * h);
            let p = |a: f32, b: f32| Vec3::new(x0 + a * h, y, z0 + b * h);
            let (a, b, c, d) = (p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0));
            let tris = if up {
                [[a, d, c], [a, c, b]]
            } else {
                [[a, b, c], [a, c, d]]
            };
            for t in tris {
                out.push(Patch::new(t, Vec3::splat(rho), Vec3::splat(e)));
            }
        }
    }
    out
}

/// Two parallel, directly opposed unit squares one apart: the form factor between them
/// is 0.199825 (Howell's catalogue, case C-11). Averaged over the first square's cells
/// (each a hemicube at its centre), the hemicube gives it within 1 %.
#[test]
fn form_factor_of_parallel_squares_matches_the_closed_form() {
    let lower = square(0.0, 1.0, 8, true, 0.5, 0.0);
    let upper = square(1.0, 1.0, 4, false, 0.5, 0.0);
    let n_lower = lower.len();
    let mut all = lower;
    all.extend(upper);
    assert!(all[0].normal().y > 0.99 && all[n_lower].normal().y < -0.99);
    let mut cube = Hemicube::new(256);
    let (mut f, mut area) = (0.0f64, 0.0f64);
    for k in 0..n_lower {
        let (p, n, a) = (all[k].centre(), all[k].normal(), all[k].area());
        let ff = cube.form_factors(&all, p + n * 1e-5, n, 1e-5);
        let to_upper: f32 = ff[n_lower..].iter().sum();
        f += f64::from(to_upper) * f64::from(a);
        area += f64::from(a);
    }
    let f = f / area;
    let want = 0.199_825;
    eprintln!("parallel unit squares: hemicube {f:.5}, closed form {want}");
    assert!((f - want).abs() < 0.01 * want, "{f} against {want}");
}

/// A closed white room (a cube seen from inside, reflectance 0.6) with one emitting
/// cell: every shot's form factors sum to 1 (the room is closed), and at the end the
/// power absorbed plus the power still unshot is the power emitted.
#[test]
fn a_closed_room_conserves_energy() {
    let rho = 0.6;
    let mut room = Vec::new();
    for (axis, sign) in [
        (0usize, 1.0f32),
        (0, -1.0),
        (1, 1.0),
        (1, -1.0),
        (2, 1.0),
        (2, -1.0),
    ] {
        // A face of the cube [-1, 1]³ at coordinate `sign` on `axis`, facing inwards.
        for t in square(0.0, 2.0, 6, sign < 0.0, rho, 0.0) {
            let corners = t.corners.map(|c| {
                let (u, w) = (c.x, c.z);
                let mut v = [0.0f32; 3];
                v[axis] = sign;
                v[(axis + 1) % 3] = u;
                v[(axis + 2) % 3] = w;
                Vec3::from_array(v)
            });
            // Keep the triangle facing the room's centre.
            let mut q = Patch::new(corners, Vec3::splat(rho), Vec3::ZERO);
            if q.normal().dot(-q.centre()) < 0.0 {
                q.corners.swap(1, 2);
            }
            room.push(q);
        }
    }
    room[5] = Patch::new(room[5].corners, Vec3::splat(rho), Vec3::splat(10.0));
    let mut cube = Hemicube::new(128);
    // Closed: the form factors from any patch sum to 1.
    for k in [0, 40, 100, 200] {
        let (p, n) = (room[k].centre(), room[k].normal());
        let sum: f32 = cube.form_factors(&room, p + n * 1e-5, n, 1e-5).iter().sum();
        assert!(
            (sum - 1.0).abs() < 5e-3,
            "patch {k}: form factors sum to {sum}"
        );
    }
    let emitted: f64 = room
        .iter()
        .map(|q| f64::from(power(q.emission) * q.area()))
        .sum();
    let solved = solve(&mut room, &mut cube, 1e-3, 2000);
    // Absorbed: (1 - ρ) of what each patch received, H = (B - E) / ρ.
    let absorbed: f64 = room
        .iter()
        .map(|q| {
            let h = (power(q.radiosity) - power(q.emission)) / rho;
            f64::from((1.0 - rho) * h * q.area())
        })
        .sum();
    let unshot: f64 = room
        .iter()
        .map(|q| f64::from(power(q.unshot) * q.area()))
        .sum();
    eprintln!(
        "closed room: {} shots, emitted {emitted:.3}, absorbed {absorbed:.3}, unshot {unshot:.4}",
        solved.shots
    );
    assert!(
        (absorbed + unshot - emitted).abs() < 0.01 * emitted,
        "absorbed {absorbed} + unshot {unshot} against emitted {emitted}"
    );
}
