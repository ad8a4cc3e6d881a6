//! Scene files read by their format, told by the extension.

use fogbank_render::{parse_scene, DEFAULT_SCENE};
use fogbank_scene::{read_scene_source, SceneFormat};

#[test]
fn scene_files_are_read_by_their_format() {
    let dir = std::env::temp_dir().join(format!("fogbank-scene-source-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let toml = dir.join("s.toml");
    std::fs::write(&toml, DEFAULT_SCENE).unwrap();
    assert_eq!(SceneFormat::of(&toml), SceneFormat::Toml);
    let src = read_scene_source(&toml, &[]).unwrap();
    assert_eq!(
        (src.text.as_str(), src.base.as_path()),
        (DEFAULT_SCENE, dir.as_path())
    );
    // Defines belong to formats with defaults; a TOML file has none.
    let e = read_scene_source(&toml, &[("spp".into(), "4".into())])
        .unwrap_err()
        .0;
    assert!(e.contains("s.toml") && e.contains("\"spp\""), "{e}");
    let xml = dir.join("S.XML");
    std::fs::write(
        &xml,
        r#"<scene version="3.0.0"><default name="w" value="8"/>
           <sensor type="perspective"><float name="fov" value="40"/>
           <film type="hdrfilm"><integer name="width" value="$w"/><integer name="height" value="4"/><rfilter type="box"/></film>
           </sensor></scene>"#,
    )
    .unwrap();
    assert!(SceneFormat::of(&xml).takes_defines());
    let src = read_scene_source(&xml, &[("w".into(), "16".into())]).unwrap();
    let desc = parse_scene(&src.text, &src.origin, &[]).unwrap();
    assert_eq!(desc.camera.width, 16);
    let e = read_scene_source(&dir.join("missing.toml"), &[])
        .unwrap_err()
        .0;
    assert!(e.contains("missing.toml"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
