//! Mesh files for tessella (being written).
