//! Tests of the spectrum command's helpers.

use super::*;

#[test]
fn decimals_print_every_step_exactly() {
    assert_eq!(decimals_of(1.0), 0);
    assert_eq!(decimals_of(0.1), 1);
    assert_eq!(decimals_of(0.25), 2);
    assert_eq!(decimals_of(1.0 / 3.0), 9);
}
