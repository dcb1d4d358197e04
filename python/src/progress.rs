//! Where `reference` and `compare` report progress (the reference's line, each method's figures
//! as it is measured): `progress=None` writes to a terminal's stderr, and inside a Jupyter kernel to
//! the cell (its `sys.stderr`), else nowhere; `True` always to Python's `sys.stderr`, `False`
//! nowhere, a callable gets each line. Lines are written from the thread that runs the work, with
//! the GIL taken for each.

use pyo3::prelude::*;
use std::io::IsTerminal;

pub enum Lines {
    Quiet,
    Terminal,
    /// Called with each line: a callable of the caller's, or `sys.stderr.write`.
    Python(Py<PyAny>, bool),
}

impl Lines {
    pub fn from_arg(py: Python<'_>, progress: Option<&Bound<'_, PyAny>>) -> PyResult<Lines> {
        let stderr = || -> PyResult<Lines> {
            Ok(Lines::Python(
                py.import("sys")?.getattr("stderr")?.unbind(),
                true,
            ))
        };
        match progress {
            None => {
                if std::io::stderr().is_terminal() {
                    Ok(Lines::Terminal)
                } else if py
                    .import("sys")?
                    .getattr("modules")?
                    .contains("ipykernel")?
                {
                    stderr()
                } else {
                    Ok(Lines::Quiet)
                }
            }
            Some(p) if p.is_callable() => Ok(Lines::Python(p.clone().unbind(), false)),
            Some(p) => match p.extract::<bool>() {
                Ok(true) => stderr(),
                Ok(false) => Ok(Lines::Quiet),
                Err(_) => Err(crate::PenumbraError::new_err(format!(
                    "progress={}: give None, True, False or a callable taking a line",
                    p.repr()?
                ))),
            },
        }
    }

    /// Reports one line; a failing callable is reported once by Python and then ignored, so the
    /// work it watches goes on.
    pub fn line(&self, line: &str) {
        match self {
            Lines::Quiet => {}
            Lines::Terminal => eprintln!("{line}"),
            Lines::Python(target, is_stream) => Python::attach(|py| {
                let sent = if *is_stream {
                    target
                        .call_method1(py, "write", (format!("{line}\n"),))
                        .and_then(|_| target.call_method0(py, "flush"))
                } else {
                    target.call1(py, (line,))
                };
                if let Err(e) = sent {
                    e.print(py);
                }
            }),
        }
    }
}
