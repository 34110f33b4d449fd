//! Shape descriptors field users expect (axes, Zingg class, isoperimetric ratio).
