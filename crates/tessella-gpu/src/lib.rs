//! GPU backend for tessella (being written).
