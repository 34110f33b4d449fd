//! Toppling under ground shaking (being written).
