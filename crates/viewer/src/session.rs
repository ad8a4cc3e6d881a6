//! A render session: one scene rendering progressively on a worker thread
//! (CPU pool or GPU backend), publishing a snapshot of its film after every
//! pass. Any change to the scene stops the session and starts a new one,
//! so accumulation restarts; the image of a session is the same function of
//! (scene, seed, sample index) as `fogbank render`'s.

use fogbank::{Film, Progress, RenderOptions, Scene};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

/// Where a session renders.
#[derive(Clone)]
pub enum Backend {
    Cpu { threads: usize },
    Gpu(Arc<fogbank::Gpu>),
}

impl Backend {
    pub fn name(&self) -> &'static str {
        match self {
            Backend::Cpu { .. } => "cpu",
            Backend::Gpu(_) => "gpu",
        }
    }
}

/// What the window shows of a session: the film's mean and the variance
/// of its mean, and how far it has come.
#[derive(Clone)]
pub struct Snapshot {
    pub width: u32,
    pub height: u32,
    pub mean: Vec<[f32; 3]>,
    pub variance: Vec<[f32; 3]>,
    /// Passes complete in every pixel (samples per pixel).
    pub spp: u32,
    /// Render time so far (seconds), upload and display excluded.
    pub seconds: f64,
    /// Pixel samples so far (primary rays).
    pub samples: u64,
}

impl Snapshot {
    fn of(film: &Film, seconds: f64) -> Snapshot {
        Snapshot {
            width: film.width,
            height: film.height,
            mean: film.mean(),
            variance: film.variance_of_mean(),
            spp: film.min_spp(),
            seconds,
            samples: film.total_samples(),
        }
    }

    /// Milliseconds per pass (per sample per pixel).
    pub fn ms_per_pass(&self) -> f64 {
        if self.spp == 0 {
            0.0
        } else {
            1e3 * self.seconds / self.spp as f64
        }
    }

    /// Primary rays per second, in millions.
    pub fn mrays_per_s(&self) -> f64 {
        if self.seconds > 0.0 {
            self.samples as f64 / self.seconds / 1e6
        } else {
            0.0
        }
    }
}

pub struct Session {
    progress: Arc<Progress>,
    latest: Arc<Mutex<Option<Arc<Snapshot>>>>,
    error: Arc<Mutex<Option<String>>>,
    worker: Option<JoinHandle<()>>,
}

impl Session {
    /// Starts rendering `scene` (up to `max_spp` passes) on `backend`;
    /// `on_pass` is called from the worker after each snapshot (the window
    /// asks for a repaint there).
    pub fn start(
        scene: Scene,
        backend: Backend,
        max_spp: u32,
        on_pass: Arc<dyn Fn() + Send + Sync>,
    ) -> Session {
        let progress = Arc::new(Progress::default());
        let latest = Arc::new(Mutex::new(None));
        let error = Arc::new(Mutex::new(None));
        let (p, l, e) = (progress.clone(), latest.clone(), error.clone());
        let worker = std::thread::spawn(move || {
            let opts = RenderOptions::new(max_spp, scene.desc.render.seed);
            let mut publish = |film: &Film, seconds: f64| {
                *l.lock().unwrap() = Some(Arc::new(Snapshot::of(film, seconds)));
                on_pass();
            };
            let renderer = match &backend {
                Backend::Cpu { threads } => fogbank::Renderer::cpu(*threads),
                Backend::Gpu(gpu) => Ok(fogbank::Renderer::gpu(gpu.clone(), 1)),
            };
            let whole = fogbank::Piece::whole(max_spp);
            let result = renderer
                .and_then(|r| r.render(&scene, &opts, &whole, &p, Some(&mut publish)))
                .map(|_| ())
                .map_err(|e| e.message);
            if let Err(msg) = result {
                *e.lock().unwrap() = Some(msg);
                on_pass();
            }
        });
        Session {
            progress,
            latest,
            error,
            worker: Some(worker),
        }
    }

    /// The newest snapshot (None before the first pass); shared, so a
    /// repaint copies no pixels and can tell whether it changed.
    pub fn snapshot(&self) -> Option<Arc<Snapshot>> {
        self.latest.lock().unwrap().clone()
    }

    /// Why the session stopped, if it failed (e.g. an integrator without a
    /// GPU kernel on the GPU backend).
    pub fn error(&self) -> Option<String> {
        self.error.lock().unwrap().clone()
    }

    /// Whether the worker has finished (all passes done, failed or stopped).
    pub fn finished(&self) -> bool {
        self.worker.as_ref().is_none_or(|w| w.is_finished())
    }

    /// Stops the worker and waits for it: rows not yet started are skipped,
    /// so this returns within about one row of work.
    pub fn stop(&mut self) {
        self.progress.cancel.store(true, Ordering::SeqCst);
        if let Some(w) = self.worker.take() {
            let _ = w.join();
        }
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        self.stop();
    }
}
