use axmpm_core::grid::GridGeometry;
use axmpm_core::particles::Particles;
use axmpm_core::interpolation::*;
fn run<S: ShapeFunction>(g: &GridGeometry, p: &Particles) {
    let mut st = Stencil::default();
    let t = std::time::Instant::now();
    let mut acc = 0.0;
    for _ in 0..20 {
        for i in 0..p.len() {
            S::stencil(g, p, i, true, &mut st);
            acc += st.weight[0] + st.gradient[1][0];
        }
    }
    let ns = t.elapsed().as_secs_f64() / (20.0 * p.len() as f64) * 1e9;
    println!("{}: {:.1} ns per stencil ({acc:.1})", S::NAME, ns);
}
fn main() {
    let g = GridGeometry::new([0.0, 0.0], [0.4, 0.3], 0.001);
    let mut p = Particles::default();
    for j in 0..400 { for i in 0..200 {
        let x = [0.00025 + i as f64 * 0.0005, 0.00025 + j as f64 * 0.0005];
        p.push(x, [0.0; 2], 1.0, 1.0, [0.00025; 2], [0.0; 4], 0);
        p.corners.push(Particles::rectangle_corners(x, [0.00025; 2]));
    }}
    run::<Linear>(&g, &p); run::<UGimp>(&g, &p); run::<CpGimp>(&g, &p); run::<Cpdi2>(&g, &p);
}
