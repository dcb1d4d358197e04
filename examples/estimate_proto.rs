// Throwaway prototype: estimator sums against the truth (not committed).
use penumbra::frame::{frame_uniform, FrameOptions, Renderer};
use penumbra::gpu::timing::TimingMode;
use penumbra::methods::{fixed_samples::{self, regular_points, Fixed, Layout}, Method};
use penumbra::reference::{truth, ReferenceMode};
use penumbra::scene::Scene;
use penumbra::stages::twin;

fn rms(v: &[f64]) -> f64 { (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt() }

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene_name = &args[1];
    let res = args.get(2).cloned().unwrap_or("128".into());
    let settings: Vec<(u32, Layout, u32)> = args[3..].iter().map(|s| {
        let p: Vec<&str> = s.split('/').collect();
        let layout = match p[1] { "c" => Layout::Centred, "l" => Layout::Lattice, _ => Layout::Jittered };
        (p[0].parse().unwrap(), layout, p[2].parse().unwrap())
    }).collect();
    let ctx = penumbra::gpu::GpuContext::new().expect("gpu");
    let cache = truth::Cache::default_for(false);
    for (n, layout, size) in settings {
        let sc = Scene::load(scene_name, &[("resolution".into(), res.clone()), ("shadow_map_size".into(), size.to_string())]).unwrap();
        let method = Method::new(Fixed::Regular { n, layout, cull: false, estimate: false });
        let mut r = Renderer::new(&ctx, &sc, &method).unwrap();
        r.keep_intermediates();
        let f = r.frame(FrameOptions { mode: TimingMode::Frame, pictures: false }).unwrap();
        let c: fixed_samples::FixedBuffers = r.inspect().unwrap().unwrap();
        let g = &f.gbuffer;
        let cont = truth::compute(&sc, g, ReferenceMode::Continuous { m: 32, seed: 1 }, &cache).unwrap().values;
        let pts = regular_points(n, layout);
        let mut exact = vec![0f32; cont.len()];
        let want_exact = std::env::var("EXACT").is_ok();
        for &(s, t) in pts.iter().filter(|_| want_exact) {
            let img = truth::compute(&sc, g, ReferenceMode::Point { s, t }, &cache).unwrap().values;
            for (e, v) in exact.iter_mut().zip(img) { *e += v / pts.len() as f32; }
        }
        let faces = c.samples.len() / pts.len();
        // split weights: column parity, row parity
        let mut split = vec![[0f32; 2]; c.samples.len()];
        let (mut we, mut wo, mut he, mut ho) = (0f32, 0f32, 0f32, 0f32);
        for k in 0..pts.len() { let (i, j) = (k as u32 % n, k as u32 / n); if i % 2 == 0 { we += 1.0 } else { wo += 1.0 }; if j % 2 == 0 { he += 1.0 } else { ho += 1.0 } }
        for (idx, sp) in split.iter_mut().enumerate() {
            let k = idx / faces; let (i, j) = (k as u32 % n, k as u32 / n);
            if n > 1 { sp[0] = if i % 2 == 0 { 1.0 / we } else { -1.0 / wo }; sp[1] = if j % 2 == 0 { 1.0 / he } else { -1.0 / ho }; }
        }
        let mut sums = vec![[0f32; 4]; cont.len()];
        twin::estimate::estimate(&frame_uniform(&sc), &c.samples, &c.weights, &split, &c.maps, g, 0, c.samples.len(), &mut sums);
        let geo: Vec<usize> = (0..cont.len()).filter(|&i| g.is_geometry(i)).collect();
        let d = |a: &[f32], b: &[f32]| rms(&geo.iter().map(|&i| (a[i] - b[i]) as f64).collect::<Vec<_>>());
        let v = &f.visibility;
        let tot = d(v, &cont); let mapt = d(v, &exact); let samt = d(&exact, &cont);
        let s_rms = rms(&geo.iter().map(|&i| ((sums[i][0] as f64).powi(2) + (sums[i][1] as f64).powi(2)).sqrt()).collect::<Vec<_>>());
        let m_rms = rms(&geo.iter().map(|&i| sums[i][2] as f64).collect::<Vec<_>>());
        let u_rms = rms(&geo.iter().map(|&i| sums[i][3] as f64).collect::<Vec<_>>());
        let c0 = rms(&geo.iter().map(|&i| sums[i][3] as f64).collect::<Vec<_>>());
        let comb: Vec<f64> = geo.iter().map(|&i| (sums[i][2] + sums[i][3]) as f64).collect();
        let (mut dot, mut nm, mut ne) = (0f64, 0f64, 0f64);
        for (k, &i) in geo.iter().enumerate() { let e = (v[i] - exact[i]) as f64; dot += e * comb[k]; nm += comb[k] * comb[k]; ne += e * e; }
        let after: Vec<f32> = (0..v.len()).map(|i| v[i] - sums[i][2] - sums[i][3]).collect();
        println!("   M+bias: rms {:.5} corr {:.3} map/that {:.3} after {:.5}", rms(&comb), dot / (nm.sqrt() * ne.sqrt()).max(1e-12), mapt / rms(&comb).max(1e-12), d(&after, &exact));
        let cs = match layout { Layout::Centred => 0.175, Layout::Lattice => 0.3, Layout::Jittered => 0.2 };
        let ps = cs * s_rms;
        let pm = (m_rms.powi(2) + c0.powi(2)).sqrt();
        let pt = (ps * ps + pm * pm).sqrt();
        let mut cover = [0usize; 4];
        for &i in &geo {
            let sig = ((cs as f32 * cs as f32) * (sums[i][0].powi(2) + sums[i][1].powi(2)) + sums[i][2].powi(2) + sums[i][3].powi(2)).sqrt();
            let e = (v[i] - cont[i]).abs();
            for (k, mult) in [1.0f32, 2.0, 3.0, 4.0].iter().enumerate() { if e <= mult * sig + 0.01 { cover[k] += 1; } }
        }
        println!("FINAL {scene_name} n={n} {layout:?} {size}: measured {tot:.5} predicted {pt:.5} ratio {:.3} | samp pred {ps:.5} true {samt:.5} | map pred {pm:.5} true {mapt:.5} | cover k=1..4: {:.3} {:.3} {:.3} {:.3}",
            pt / tot, cover[0] as f64 / geo.len() as f64, cover[1] as f64 / geo.len() as f64, cover[2] as f64 / geo.len() as f64, cover[3] as f64 / geo.len() as f64);
        let corrected: Vec<f32> = (0..v.len()).map(|i| v[i] - sums[i][2]).collect();
        let map_after = d(&corrected, &exact);
        // sign agreement of M with true map error
        let (mut dot, mut nm, mut ne) = (0f64, 0f64, 0f64);
        for &i in &geo { let e = (v[i] - exact[i]) as f64; let m = sums[i][2] as f64; dot += e * m; nm += m * m; ne += e * e; }
        println!("{scene_name} n={n} {layout:?} {size}: total {tot:.5} map_true {mapt:.5} samp_true {samt:.5} | S {s_rms:.5} M {m_rms:.5} U {u_rms:.5} corr {:.3} map_after_M {map_after:.5} | ratios samp/S {:.3} map/M {:.3} map/U {:.3}",
            dot / (nm.sqrt() * ne.sqrt()).max(1e-12), samt / s_rms.max(1e-12), mapt / m_rms.max(1e-12), mapt / u_rms.max(1e-12));
    }
}
