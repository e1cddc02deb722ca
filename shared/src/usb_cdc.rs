//! The run log's USB serial port as data and decisions, free of the USB
//! controller: the fixed descriptors of a one-configuration CDC-ACM device
//! ([`descriptors`]), what the device does with each control request
//! ([`control`]) and endpoint 0's control transfers packet by packet
//! ([`pipe`]). The firmware's `usb` module drives the RP2040's USB
//! controller with them; here they are tested on the host.
//!
//! Why not usb-device: on the robot, usb-device with usbd-serial's
//! `CdcAcmClass` on rp2040-hal's `UsbBus` cost 10.7 kB of flash for this one
//! fixed port, and the image has to fit 32 KiB (issue 26, "Budgets"). This
//! device answers only what a CDC-ACM host asks (firmware/README.md, "Flash
//! and RAM", has the measured bytes).
//!
//! References: USB 2.0 specification, chapter 9 (standard requests and
//! descriptors); USB CDC 1.2 and its PSTN subclass 1.2 (ACM's functional
//! descriptors and requests).

pub mod control;
pub mod descriptors;
pub mod pipe;

#[cfg(test)]
mod tests;
