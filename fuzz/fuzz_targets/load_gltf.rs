//! Fuzz the Glb loader without its panic guard, then the repair and connectivity build on
//! whatever it accepts: no panic anywhere, and every built mesh must validate.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(m) = dynlod::io::load_bytes_unguarded(data, dynlod::io::Format::Glb, None) {
        if let Ok(mesh) = dynlod::Mesh::build(&m, dynlod::BuildOptions::default()) {
            mesh.topology.validate().expect("built mesh must validate");
        }
    }
});
