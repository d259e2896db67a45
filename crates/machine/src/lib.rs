//! Machines: the [`Machine`] trait and the built-in virtual machine.
