//! Exact: the max-mip traversal (Tevs et al. 2008), exact.wgsl over maxmip.wgsl.
use crate::contract::{check_range, PerPixel, Spec, Unit};
use crate::error::Result;

crate::params! {
    pub struct Exact {
        pub max_iterations: u32,
    }
}

impl Unit for Exact {
    fn examples() -> Vec<Self> {
        vec![Exact {
            max_iterations: 4096,
        }]
    }
    fn spec(&self, o: &PerPixel) -> Spec {
        let wgsl = crate::method_shader!("exact");
        let mut s = Spec::surface(wgsl, o, &[]);
        s.max_iterations = self.max_iterations;
        s
    }
    fn validate(&self) -> Result<()> {
        check_range("max_iterations", self.max_iterations, 1, 1 << 24)
    }
}
