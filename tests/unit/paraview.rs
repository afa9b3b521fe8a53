//! The ParaView files of a box run (`harness::run::paraview`) as a library: the collection is XML
//! whatever the file names, lists its snapshots in the order given, the obstacle beside each;
//! the obstacle exists for 2D and 3D boxes only.

use signorini::harness::run::paraview::{collection_xml, obstacle_vtk, Snapshot};

/// The `(timestep, part, file)` of each `<DataSet>` of the collection `xml`.
fn datasets(xml: &str) -> Vec<(String, String, String)> {
    let doc = roxmltree::Document::parse(xml).unwrap();
    assert_eq!(doc.root_element().attribute("type"), Some("Collection"));
    doc.descendants()
        .filter(|n| n.has_tag_name("DataSet"))
        .map(|n| {
            let a = |name: &str| n.attribute(name).unwrap().to_string();
            (a("timestep"), a("part"), a("file"))
        })
        .collect()
}

#[test]
fn a_collection_is_xml_whatever_its_file_names_and_keeps_every_digit_of_its_times() {
    let odd = "a&b<c>\"d'e.vtu";
    let third = 0.1 + 0.2;
    let snapshots = [
        Snapshot {
            time: third,
            file: odd.to_string(),
        },
        Snapshot {
            time: 2.0,
            file: "field-t2.vtu".to_string(),
        },
    ];
    let listed = datasets(&collection_xml(&snapshots, Some("obstacle.vtu")));
    let entry = |t: &str, p: &str, f: &str| (t.to_string(), p.to_string(), f.to_string());
    assert_eq!(
        listed,
        [
            entry(&third.to_string(), "0", odd),
            entry(&third.to_string(), "1", "obstacle.vtu"),
            entry("2", "0", "field-t2.vtu"),
            entry("2", "1", "obstacle.vtu"),
        ]
    );
    assert_eq!(listed[0].0.parse::<f64>().unwrap(), third);
    let alone = datasets(&collection_xml(&snapshots, None));
    assert_eq!(
        alone,
        [
            entry(&third.to_string(), "0", odd),
            entry("2", "0", "field-t2.vtu")
        ]
    );
    assert!(datasets(&collection_xml(&[], None)).is_empty());
}

#[test]
fn only_a_2d_or_3d_box_has_an_obstacle() {
    assert!(obstacle_vtk(&[0.1, 1.0], 0.2).is_some());
    assert!(obstacle_vtk(&[0.1, 0.1, 1.0], 0.2).is_some());
    for lengths in [&[][..], &[1.0], &[0.1, 0.1, 0.1, 1.0]] {
        assert!(obstacle_vtk(lengths, 0.2).is_none(), "{lengths:?}");
    }
}
