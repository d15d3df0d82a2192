//! Reading input files: only regular files, so that a FIFO, a device or a folder named as
//! a scene, settings file, buffer or image is refused at once instead of blocking or
//! reading without end.

use std::io;
use std::path::Path;

/// The bytes of `path`, which must be a regular file (links are followed).
pub fn read_regular_file(path: &Path) -> io::Result<Vec<u8>> {
    let kind = std::fs::metadata(path)?.file_type();
    if !kind.is_file() {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, format!("not a regular file ({})", describe(kind))));
    }
    std::fs::read(path)
}

fn describe(kind: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_socket() {
            return "a socket";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
    }
    if kind.is_dir() { "a folder" } else { "not a file" }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_and_fifos_are_refused() {
        let dir = std::env::temp_dir().join(format!("chiaro-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let e = read_regular_file(&dir).unwrap_err();
        assert_eq!(e.to_string(), "not a regular file (a folder)");
        #[cfg(unix)]
        {
            let fifo = dir.join("pipe");
            let status = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
            assert!(status.success());
            let e = read_regular_file(&fifo).unwrap_err();
            assert_eq!(e.to_string(), "not a regular file (a FIFO)");
        }
        let file = dir.join("f.txt");
        std::fs::write(&file, b"x").unwrap();
        assert_eq!(read_regular_file(&file).unwrap(), b"x");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
