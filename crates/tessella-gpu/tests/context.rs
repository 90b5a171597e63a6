//! Adapter choice and error messages.

mod common;

use tessella_gpu::{AdapterChoice, GpuContext, GpuError};

#[test]
fn software_choice_gives_a_software_adapter_with_a_label() {
    let ctx = common::ctx();
    assert!(ctx.is_software());
    assert!(ctx.adapter_label().contains("software"));
    assert!(ctx.max_binding() >= 128 << 20);
}

#[test]
fn hardware_choice_never_returns_a_software_adapter() {
    match GpuContext::new(AdapterChoice::Hardware) {
        Ok(ctx) => assert!(!ctx.is_software(), "got {}", ctx.adapter_label()),
        Err(e) => {
            assert!(matches!(e, GpuError::NoAdapter { .. }), "{e}");
            let message = e.to_string();
            assert!(message.contains("no hardware GPU adapter"), "{message}");
            assert!(message.contains("CPU backend"), "{message}");
        }
    }
}
