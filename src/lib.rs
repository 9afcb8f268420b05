//! confset
