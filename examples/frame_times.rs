//! Wall clock of each frame of one method on the analytic square through the embedding API, after
//! one untimed warm-up frame: the Rust side of scripts/python-overhead.py, which times the same
//! frames through the Python package.
//!
//! ```sh
//! cargo run --release --example frame_times -- [METHOD] [SIZE] [FRAMES]   # one line per frame, ms
//! ```

#[allow(dead_code)]
#[path = "embed.rs"]
mod embed;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let method = args
        .first()
        .map_or("adaptive:preset=balanced", String::as_str);
    let number = |i: usize, default: u32| args.get(i).map_or(Ok(default), |s| s.parse::<u32>());
    let (Ok(size), Ok(frames)) = (number(1, 64), number(2, 20)) else {
        eprintln!("frame_times: SIZE and FRAMES must be positive integers");
        std::process::exit(2)
    };
    let run = || -> Result<Vec<f64>, String> {
        let (adapter, device, queue) = embed::app_device()?;
        let shadows =
            penumbra::Shadows::new(&adapter, &device, &queue).map_err(|e| e.to_string())?;
        let scene = embed::analytic_square(size).map_err(|e| e.to_string())?;
        let mut renderer = shadows
            .renderer(&scene, method)
            .map_err(|e| e.to_string())?;
        renderer.render().map_err(|e| e.to_string())?;
        (0..frames)
            .map(|_| {
                let start = std::time::Instant::now();
                renderer.render().map_err(|e| e.to_string())?;
                Ok(start.elapsed().as_secs_f64() * 1e3)
            })
            .collect()
    };
    match run() {
        Ok(ms) => ms.iter().for_each(|t| println!("{t:.4}")),
        Err(e) => {
            eprintln!("frame_times: {e}");
            std::process::exit(1)
        }
    }
}
