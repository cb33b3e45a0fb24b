//! [`Up`]: the up axis of a model.

/// Which world axis points up in a model: the renderer's camera turns with it, and the
/// glTF writer turns it to glTF's `+Y` up.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Up {
    /// `+Z` up (OpenSubdiv's shapes, CAD); azimuth 0 looks along `+Y`.
    #[default]
    Z,
    /// `+Y` up (most OBJ exporters); azimuth 0 looks along `−Z`.
    Y,
}
