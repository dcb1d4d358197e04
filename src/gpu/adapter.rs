//! Which adapter to run on, and why: Vulkan first, then real GPUs before CPU devices. An adapter
//! that lacks what the pipeline needs (a GL adapter cannot render `Rgba32Float`) is never chosen
//! silently: the run stops at once and names the missing Vulkan driver and `scripts/setup.sh`.

use crate::{Error, Result};

/// The G-buffer's position and normal format: adapters must render to it (render::gbuffer).
pub(crate) const POSITION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// How to install a Vulkan driver on Debian/Ubuntu; every "no usable adapter" message ends with it.
pub(crate) const INSTALL_HINT: &str = "install the Vulkan driver with `bash scripts/setup.sh` \
(on Debian/Ubuntu it installs mesa-vulkan-drivers and libvulkan1: lavapipe, Mesa's CPU Vulkan device)";

/// The backend the user asked for (`--backend`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BackendChoice {
    /// Vulkan where it exists, else whatever usable adapter there is.
    #[default]
    Auto,
    Vulkan,
    Gl,
    Metal,
    Dx12,
}

impl BackendChoice {
    pub(crate) const NAMES: [&'static str; 5] = ["auto", "vulkan", "gl", "metal", "dx12"];

    pub fn parse(s: &str) -> Result<Self> {
        Ok(match s.trim().to_ascii_lowercase().as_str() {
            "auto" => Self::Auto,
            "vulkan" => Self::Vulkan,
            "gl" | "gles" | "opengl" => Self::Gl,
            "metal" => Self::Metal,
            "dx12" => Self::Dx12,
            other => {
                return Err(Error::Input {
                    input: crate::Input::Backend,
                    value: other.to_string(),
                    why: format!("expected one of {}", Self::NAMES.join(", ")),
                });
            }
        })
    }

    /// The `--backend` value that asks for this choice.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Vulkan => "vulkan",
            Self::Gl => "gl",
            Self::Metal => "metal",
            Self::Dx12 => "dx12",
        }
    }

    pub(crate) fn backends(self) -> wgpu::Backends {
        match self {
            Self::Auto => wgpu::Backends::all(),
            Self::Vulkan => wgpu::Backends::VULKAN,
            Self::Gl => wgpu::Backends::GL,
            Self::Metal => wgpu::Backends::METAL,
            Self::Dx12 => wgpu::Backends::DX12,
        }
    }
}

/// What the user asked for: a backend and, optionally, part of an adapter's name.
#[derive(Clone, Debug, Default)]
pub struct AdapterRequest {
    pub backend: BackendChoice,
    pub name: Option<String>,
    /// Where the request came from, for the "why" line (e.g. `--backend`, `WGPU_BACKEND`).
    pub source: Option<String>,
}

/// One adapter as the chooser sees it.
#[derive(Clone, Debug)]
pub(crate) struct Candidate {
    pub(crate) name: String,
    pub(crate) backend: wgpu::Backend,
    pub(crate) device_type: wgpu::DeviceType,
    /// What the pipeline needs that this adapter lacks; empty when usable.
    pub(crate) missing: Vec<String>,
}

impl Candidate {
    pub(crate) fn of(adapter: &wgpu::Adapter) -> Self {
        let info = adapter.get_info();
        Self {
            name: info.name,
            backend: info.backend,
            device_type: info.device_type,
            missing: missing_capabilities(adapter),
        }
    }

    fn label(&self) -> String {
        format!("{} ({:?}, {:?})", self.name, self.backend, self.device_type)
    }
}

/// The adapter chosen (index into the candidates) and the reason, for `penumbra info` and run.json.
#[derive(Clone, Debug)]
pub(crate) struct Choice {
    pub(crate) index: usize,
    pub(crate) reason: String,
}

/// What the pipeline needs beyond the WebGPU baseline, checked before any pipeline is built.
pub(crate) fn missing_capabilities(adapter: &wgpu::Adapter) -> Vec<String> {
    let mut missing = Vec::new();
    let down = adapter.get_downlevel_capabilities();
    if !down.flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS) {
        missing.push("compute shaders".to_string());
    }
    let position = POSITION_FORMAT;
    let usages = adapter.get_texture_format_features(position).allowed_usages;
    if !usages.contains(wgpu::TextureUsages::RENDER_ATTACHMENT) {
        missing.push(format!(
            "the G-buffer format {position:?} is not renderable"
        ));
    }
    let depth = adapter
        .get_texture_format_features(wgpu::TextureFormat::Depth32Float)
        .allowed_usages;
    if !depth
        .contains(wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING)
    {
        missing.push("Depth32Float shadow maps cannot be rendered and sampled".to_string());
    }
    missing
}

fn rank(c: &Candidate) -> (u8, u8) {
    let backend = match c.backend {
        wgpu::Backend::Vulkan => 0,
        wgpu::Backend::Metal | wgpu::Backend::Dx12 => 1,
        _ => 2,
    };
    let device = match c.device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    };
    (backend, device)
}

fn wanted(req: &AdapterRequest, c: &Candidate) -> bool {
    let backend_ok = req
        .backend
        .backends()
        .contains(wgpu::Backends::from(c.backend));
    let name_ok = req
        .name
        .as_ref()
        .is_none_or(|n| c.name.to_lowercase().contains(&n.to_lowercase()));
    backend_ok && name_ok
}

/// Picks the best usable adapter for `req`, or says exactly why there is none.
pub(crate) fn choose(candidates: &[Candidate], req: &AdapterRequest) -> Result<Choice> {
    let seen = if candidates.is_empty() {
        "none".to_string()
    } else {
        candidates
            .iter()
            .map(Candidate::label)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut order: Vec<usize> = (0..candidates.len())
        .filter(|&i| wanted(req, &candidates[i]))
        .collect();
    order.sort_by_key(|&i| rank(&candidates[i]));
    let source = req.source.as_deref().unwrap_or("backend");
    let asked = match req.backend {
        BackendChoice::Auto => None,
        b => Some(format!("{source} {}", format!("{b:?}").to_lowercase())),
    };
    if order.is_empty() {
        return Err(Error::NoAdapter(match (&asked, &req.name) {
            (None, None) => format!("no GPU adapter found (no Vulkan driver): {INSTALL_HINT}"),
            (asked, name) => {
                let mut what = Vec::new();
                what.extend(
                    asked
                        .iter()
                        .map(|a| format!("{a}: no {:?} adapter", req.backend)),
                );
                what.extend(
                    name.iter()
                        .map(|n| format!("adapter name \"{n}\": no adapter's name contains it")),
                );
                let hint = if req.backend == BackendChoice::Vulkan {
                    format!("; {INSTALL_HINT}")
                } else {
                    String::new()
                };
                format!("{} (adapters seen: {seen}){hint}", what.join("; "))
            }
        }));
    }
    if let Some(&index) = order.iter().find(|&&i| candidates[i].missing.is_empty()) {
        let c = &candidates[index];
        let reason = match req.backend {
            BackendChoice::Auto if c.backend == wgpu::Backend::Vulkan => {
                format!("auto: Vulkan preferred, then real GPUs before CPU devices (adapters seen: {seen})")
            }
            BackendChoice::Auto => format!(
                "auto: no usable Vulkan adapter, so {:?} (adapters seen: {seen})",
                c.backend
            ),
            _ => format!(
                "{} (adapters seen: {seen})",
                asked.clone().unwrap_or_default()
            ),
        };
        let reason = match &req.name {
            Some(n) => format!("{reason}; name contains \"{n}\""),
            None => reason,
        };
        return Ok(Choice { index, reason });
    }
    // Adapters exist but none can run the pipeline: say what each lacks.
    let lacks: Vec<String> = order
        .iter()
        .map(|&i| {
            format!(
                "{} cannot run penumbra: {}",
                candidates[i].label(),
                candidates[i].missing.join("; ")
            )
        })
        .collect();
    let vulkan_seen = candidates
        .iter()
        .any(|c| c.backend == wgpu::Backend::Vulkan);
    let lead = match asked {
        Some(a) => format!("{a}: no usable adapter"),
        None if vulkan_seen => "no usable adapter".to_string(),
        None => "no Vulkan driver found".to_string(),
    };
    Err(Error::NoAdapter(format!(
        "{lead}: {}; {INSTALL_HINT}",
        lacks.join("; ")
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgpu::{Backend, DeviceType};

    fn cand(name: &str, backend: Backend, device_type: DeviceType, missing: &[&str]) -> Candidate {
        Candidate {
            name: name.into(),
            backend,
            device_type,
            missing: missing.iter().map(|m| m.to_string()).collect(),
        }
    }

    fn gl_only() -> Vec<Candidate> {
        vec![cand(
            "llvmpipe",
            Backend::Gl,
            DeviceType::Cpu,
            &["the G-buffer format Rgba32Float is not renderable"],
        )]
    }

    #[test]
    fn vulkan_is_preferred_then_real_gpus() {
        let c = vec![
            cand("llvmpipe", Backend::Gl, DeviceType::Cpu, &[]),
            cand("llvmpipe", Backend::Vulkan, DeviceType::Cpu, &[]),
            cand("big", Backend::Vulkan, DeviceType::DiscreteGpu, &[]),
        ];
        let choice = choose(&c, &AdapterRequest::default()).unwrap();
        assert_eq!(choice.index, 2);
        assert!(
            choice.reason.starts_with("auto: Vulkan preferred"),
            "{}",
            choice.reason
        );
        let gl = AdapterRequest {
            backend: BackendChoice::Gl,
            name: None,
            source: Some("--backend".into()),
        };
        let choice = choose(&c, &gl).unwrap();
        assert_eq!(choice.index, 0);
        assert!(
            choice.reason.starts_with("--backend gl"),
            "{}",
            choice.reason
        );
    }

    #[test]
    fn a_gl_only_machine_stops_at_once_naming_the_vulkan_driver_and_setup_script() {
        let e = choose(&gl_only(), &AdapterRequest::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("no Vulkan driver found: llvmpipe (Gl, Cpu) cannot run penumbra: "),
            "{e}"
        );
        assert!(e.contains("Rgba32Float is not renderable"), "{e}");
        assert!(
            e.contains("`bash scripts/setup.sh`") && e.contains("mesa-vulkan-drivers"),
            "{e}"
        );
        assert!(!e.contains('\n'), "one line: {e}");
    }

    #[test]
    fn no_adapter_and_unmatched_requests_say_what_was_seen() {
        let e = choose(&[], &AdapterRequest::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no GPU adapter found") && e.contains("scripts/setup.sh"),
            "{e}"
        );
        let dx = AdapterRequest {
            backend: BackendChoice::Dx12,
            name: None,
            source: Some("WGPU_BACKEND".into()),
        };
        let e = choose(&gl_only(), &dx).unwrap_err().to_string();
        assert_eq!(
            e,
            "WGPU_BACKEND dx12: no Dx12 adapter (adapters seen: llvmpipe (Gl, Cpu))"
        );
        let named = AdapterRequest {
            name: Some("NVIDIA".into()),
            ..Default::default()
        };
        let e = choose(&gl_only(), &named).unwrap_err().to_string();
        assert!(
            e.starts_with("adapter name \"NVIDIA\": no adapter's name contains it"),
            "{e}"
        );
    }

    #[test]
    fn an_unusable_vulkan_adapter_is_passed_over_for_a_usable_one() {
        let c = vec![
            cand(
                "broken",
                Backend::Vulkan,
                DeviceType::DiscreteGpu,
                &["compute shaders"],
            ),
            cand("lavapipe", Backend::Vulkan, DeviceType::Cpu, &[]),
        ];
        assert_eq!(choose(&c, &AdapterRequest::default()).unwrap().index, 1);
    }

    #[test]
    fn backend_names_parse_and_a_wrong_one_lists_the_choices() {
        assert_eq!(
            BackendChoice::parse("Vulkan").unwrap(),
            BackendChoice::Vulkan
        );
        assert_eq!(BackendChoice::parse("gles").unwrap(), BackendChoice::Gl);
        let e = BackendChoice::parse("cuda").unwrap_err().to_string();
        assert_eq!(
            e,
            "backend cuda: expected one of auto, vulkan, gl, metal, dx12"
        );
    }
}
