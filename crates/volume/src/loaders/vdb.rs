//! OpenVDB reader (in progress).
