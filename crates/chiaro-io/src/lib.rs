//! Files in and out, shared by the command line and the viewer. In: a scene file (or the
//! built-in demo) and a settings file, read with errors that name the file; the bake that
//! lights the scene; the view a camera choice gives. Out: output paths checked before any
//! work, and images and files written atomically as a group, in the encodings Chiaro
//! writes (PNG, OpenEXR).

pub mod bake;
pub mod device;
pub mod output;
pub mod scenes;
