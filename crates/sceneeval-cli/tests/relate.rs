//! `sceneeval relate`: JSON-lines queries in, one answer per line out; bad lines get an error
//! answer and processing goes on.

// Helpers outside `#[test]` functions parse the binary's own output.
#![allow(clippy::unwrap_used)]

use assert_cmd::Command;
use serde_json::{Value, json};

const BED: &str = r#"{"center":[0,0,0.3],"half_size":[0.8,1.0,0.3],"yaw":0.0}"#;
const ROOM: &str = r#"{"floor":[[0,0],[4,0],[4,5],[0,5]],"floor_z":0.0,"height":2.8,"wall_thickness":0.1,
    "openings":[{"kind":"door","wall":0,"along":[1.0,1.9],"height":[0.0,2.1]}]}"#;

/// Runs `sceneeval relate` on `input` (lines joined with newlines) and returns the exit code
/// and the parsed answer lines.
fn relate(args: &[&str], input: &str) -> (i32, Vec<Value>) {
    let out = Command::cargo_bin("sceneeval")
        .unwrap()
        .arg("relate")
        .args(args)
        .write_stdin(input)
        .output()
        .unwrap();
    let answers = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    (out.status.code().unwrap(), answers)
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join("")
}

fn score(answer: &Value) -> f64 {
    answer["score"].as_f64().unwrap()
}

#[test]
fn the_four_forms_of_the_issue() {
    let q1 = format!(
        r#"{{"id":"q1","relation":"side_of","side":"left",
            "target":{{"center":[-1.05,0.5,0.3],"half_size":[0.25,0.2,0.3],"yaw":1.5707963267948966}},
            "anchor":{BED}}}"#
    );
    let chair = |x: f64, y: f64| format!(r#"{{"center":[{x},{y},0.4],"half_size":[0.2,0.2,0.4],"yaw":0}}"#);
    let q2 = format!(
        r#"{{"id":"q2","relation":"surround","anchor":{{"center":[0,0,0.4],"half_size":[0.5,0.5,0.4],"yaw":0}},
            "targets":[{},{},{},{}]}}"#,
        chair(1.0, 0.0),
        chair(0.0, 1.0),
        chair(-1.0, 0.0),
        chair(0.0, -1.0)
    );
    // A bed with its head against the far wall (y = 5).
    let q3 = format!(
        r#"{{"id":"q3","relation":"against_wall",
            "target":{{"center":[2.0,4.0,0.3],"half_size":[0.8,1.0,0.3],"yaw":0.0}},"room":{ROOM}}}"#
    );
    // A chair 0.2 m in front of the door (x in [1.0, 1.9] on the wall y = 0).
    let q4 = format!(
        r#"{{"id":"q4","relation":"next_to","arch":"door",
            "target":{{"center":[1.45,0.45,0.4],"half_size":[0.25,0.25,0.4],"yaw":0.0}},"room":{ROOM}}}"#
    );
    let input = [q1, q2, q3, q4].map(|q| one_line(&q)).join("\n");
    let (code, answers) = relate(&[], &input);
    assert_eq!(code, 0);
    assert_eq!(answers.len(), 4);
    // Turned 90 degrees the nightstand spans x in [-1.25, -0.85]: wholly beyond the bed's -x face.
    assert_eq!(answers[0], json!({"id": "q1", "score": 1.0, "holds": true}));
    assert_eq!(answers[1]["id"], "q2");
    assert!((score(&answers[1]) - 1.0).abs() < 1e-12, "{}", answers[1]);
    assert_eq!(answers[2], json!({"id": "q3", "score": 1.0, "holds": true}));
    assert_eq!(answers[3], json!({"id": "q4", "score": 1.0, "holds": true}));
}

#[test]
fn rotation_matrices_and_argument_forms() {
    // The same nightstand as a row-major matrix (yaw 90 degrees), nested and flat, and the
    // relation written as side_of(right): all agree (score 0 on the right).
    let nested = r#"[[0,-1,0],[1,0,0],[0,0,1]]"#;
    let flat = r#"[0,-1,0,1,0,0,0,0,1]"#;
    let lines = [
        format!(
            r#"{{"id":1,"relation":"side_of","side":"left","target":{{"center":[-1.05,0.5,0.3],"half_size":[0.25,0.2,0.3],"rotation":{nested}}},"anchor":{BED}}}"#
        ),
        format!(
            r#"{{"id":2,"relation":"side_of","side":"left","target":{{"center":[-1.05,0.5,0.3],"half_size":[0.25,0.2,0.3],"rotation":{flat}}},"anchor":{BED}}}"#
        ),
        format!(
            r#"{{"id":3,"relation":"side_of(right)","target":{{"center":[-1.05,0.5,0.3],"half_size":[0.25,0.2,0.3],"rotation":{flat}}},"anchor":{BED}}}"#
        ),
        // Straddling the face x = -0.8 (x in [-1.05, -0.55]): half beyond it, plus the 1e-6 m
        // tolerance over the 0.5 m width: 0.500002.
        format!(
            r#"{{"id":4,"relation":"side_of","side":"left","target":{{"center":[-0.8,0.5,0.3],"half_size":[0.25,0.2,0.3],"yaw":0}},"anchor":{BED}}}"#
        ),
    ];
    let (code, answers) = relate(&[], &lines.join("\n"));
    assert_eq!(code, 0, "{answers:?}");
    assert_eq!(score(&answers[0]), 1.0);
    assert_eq!(score(&answers[1]), 1.0);
    assert_eq!(answers[2], json!({"id": 3, "score": 0.0, "holds": false}));
    assert!((score(&answers[3]) - 0.500_002).abs() < 1e-9, "{}", answers[3]);
    assert_eq!(answers[3]["holds"], true);
}

#[test]
fn bad_lines_get_errors_and_processing_goes_on() {
    let good = format!(
        r#"{{"id":"ok","relation":"near","target":{{"center":[2.0,0,0.3],"half_size":[0.2,0.2,0.3],"yaw":0}},"anchor":{BED}}}"#
    );
    let lines = [
        good.clone(),
        "{this is not json".to_owned(),
        r#"{"id":"unknown","relation":"beside","target":{"center":[0,0,0],"half_size":[1,1,1],"yaw":0},"anchor":{"center":[0,0,0],"half_size":[1,1,1],"yaw":0}}"#.to_owned(),
        format!(r#"{{"id":"noside","relation":"side_of","target":{BED},"anchor":{BED}}}"#),
        format!(
            r#"{{"id":"inf","relation":"near","target":{{"center":[1e999,0,0],"half_size":[1,1,1],"yaw":0}},"anchor":{BED}}}"#
        ),
        format!(
            r#"{{"id":"nan","relation":"near","target":{{"center":[NaN,0,0],"half_size":[1,1,1],"yaw":0}},"anchor":{BED}}}"#
        ),
        format!(
            r#"{{"id":"shear","relation":"near","target":{{"center":[0,0,0],"half_size":[1,1,1],"rotation":[1,0.5,0,0,1,0,0,0,1]}},"anchor":{BED}}}"#
        ),
        format!(r#"{{"id":"noanchor","relation":"near","target":{BED}}}"#),
        format!(r#"{{"id":"nodoor","relation":"next_to","target":{BED},"room":{}}}"#, one_line(ROOM)),
        format!(r#"{{"id":"floor","relation":"next_to","arch":"floor","target":{BED},"room":{}}}"#, one_line(ROOM)),
        format!(r#"{{"id":"neg","relation":"near","target":{{"center":[0,0,0],"half_size":[-1,1,1],"yaw":0}},"anchor":{BED}}}"#),
        format!(r#"{{"id":"extra","relation":"near","target":{BED},"anchor":{BED},"colour":"red"}}"#),
        format!(r#"{{"id":"v2","version":2,"relation":"near","target":{BED},"anchor":{BED}}}"#),
        String::new(),
        good,
    ];
    let (code, answers) = relate(&[], &lines.join("\n"));
    assert_eq!(code, 2, "some lines failed");
    // The blank line gets no answer.
    assert_eq!(answers.len(), lines.len() - 1);
    // The box 2 m from the bed's centre: gap 2.0 - 0.2 - 0.8 = 1.0 m, inside near's range.
    assert_eq!(answers[0], json!({"id": "ok", "score": 1.0, "holds": true}));
    assert_eq!(answers[13], answers[0]);
    let error = |i: usize| answers[i]["error"].as_str().unwrap().to_owned();
    assert_eq!(answers[1]["id"], Value::Null);
    assert!(error(1).starts_with("line 2: invalid JSON"), "{}", error(1));
    let expect = [
        (2, "unknown", "unknown relation"),
        (3, "noside", "needs a side"),
        (4, "inf", "number out of range"),
        (6, "shear", "not a valid box"),
        (7, "noanchor", "needs \"anchor\""),
        (8, "nodoor", "needs \"arch\""),
        (9, "floor", "element type"),
        (10, "neg", "not a valid box"),
        (11, "extra", "unknown field"),
        (12, "v2", "unsupported schema version 2"),
    ];
    for (i, id, text) in expect {
        assert_eq!(answers[i]["id"], id, "{}", answers[i]);
        assert!(error(i).contains(text), "{id}: {}", error(i));
        assert!(answers[i].get("score").is_none());
    }
    // NaN is not JSON at all: the id cannot be read.
    assert_eq!(answers[5]["id"], Value::Null);
    assert!(error(5).contains("invalid JSON"));
}

#[test]
fn errors_in_objects_and_rooms_name_the_key_and_the_object() {
    // Issue 29: a 2-element half_size said "invalid length 2, expected an array of length 3"
    // without naming the key or the object.
    let room = one_line(ROOM);
    let lines = [
        format!(r#"{{"id":1,"relation":"near","target":{{"center":[0,0,0],"half_size":[1,1]}},"anchor":{BED}}}"#),
        format!(r#"{{"id":2,"relation":"near","target":{BED},"anchor":{{"center":[0,0],"half_size":[1,1,1]}}}}"#),
        format!(
            r#"{{"id":3,"relation":"surround","anchor":{BED},"targets":[{BED},{{"center":[0,0,0],"half_size":[1,1]}}]}}"#
        ),
        r#"{"id":4,"declare":"lamp","object":{"center":[0,0,1],"half_size":[0.1,0.1]}}"#.to_owned(),
        // Four numbers: valid JSON, so an invalid query (serde_json reports trailing characters).
        format!(r#"{{"id":5,"relation":"near","target":{{"center":[0,0,0],"half_size":[1,1,1,1]}},"anchor":{BED}}}"#),
        r#"{"id":6,"relation":"inside_room","target":{"center":[1,1,0.5],"half_size":[0.5,0.5,0.5]},"room":{"floor":[[0,0],[4,0,1],[4,5]]}}"#.to_owned(),
        format!(r#"{{"id":7,"relation":"near","target":{{"center":[0,0,0],"half_size":[1,1,1],"colour":1}},"anchor":{BED}}}"#),
        format!(r#"{{"id":8,"declare":"r","room":{}}}"#, room.replace(r#""height":2.8"#, r#""height":"high""#)),
        // Not JSON: still invalid JSON, with no path.
        r#"{"id":9,"relation":"near","target":{"center":[0,0,0],"half_size":[1,1"#.to_owned(),
    ];
    let (code, answers) = relate(&[], &lines.join("\n"));
    assert_eq!(code, 2);
    let error = |i: usize| answers[i]["error"].as_str().unwrap().to_owned();
    for (i, starts) in [
        (
            0,
            "line 1: invalid query: target.half_size: invalid length 2, expected an array of length 3 at line 1 column",
        ),
        (
            1,
            "line 2: invalid query: anchor.center: invalid length 2, expected an array of length 3 at line 1 column",
        ),
        (
            2,
            "line 3: invalid query: targets[1].half_size: invalid length 2, expected an array of length 3 at line 1 column",
        ),
        (
            3,
            r#"line 4: invalid declaration of "lamp": object.half_size: invalid length 2, expected an array of length 3"#,
        ),
        (
            4,
            "line 5: invalid query: target.half_size: trailing characters at line 1 column",
        ),
        (
            5,
            "line 6: invalid room: floor[1]: trailing characters at line 1 column",
        ),
        (
            6,
            "line 7: invalid query: target: unknown field `colour`, expected one of",
        ),
        (
            7,
            r#"line 8: declaration of "r": invalid room: height: invalid type: string "high", expected f64"#,
        ),
        (8, "line 9: invalid JSON: EOF while parsing"),
    ] {
        assert!(error(i).starts_with(starts), "{i}: {}", error(i));
    }
    // Every line but the last one (not JSON) is JSON whose id is echoed.
    for (i, answer) in answers[..8].iter().enumerate() {
        assert_eq!(answer["id"], i + 1, "{answer}");
    }
    assert_eq!(answers[8]["id"], Value::Null);
}

#[test]
fn reads_a_file_and_offers_the_reference_behaviour() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("queries.jsonl");
    // A book sunk 2 cm into a table top (z in [0.73, 0.78], top at 0.75): 3 of its 5 cm are
    // above the top face (0.6); the reference's centre plane counts all of it.
    let q = r#"{"id":"book","relation":"on_top","target":{"center":[0,0,0.755],"half_size":[0.1,0.15,0.025],"yaw":0},"anchor":{"center":[0,0,0.375],"half_size":[0.6,0.4,0.375],"yaw":0}}"#;
    std::fs::write(&path, format!("{q}\n")).unwrap();
    let file = path.to_str().unwrap();
    let (code, answers) = relate(&["--input", file], "");
    assert_eq!(code, 0);
    assert!((score(&answers[0]) - 0.6).abs() < 1e-4, "{}", answers[0]);
    assert_eq!(answers[0]["holds"], true);
    let (_, reference) = relate(&["--input", file, "--reference"], "");
    assert_eq!(reference[0], json!({"id": "book", "score": 1.0, "holds": true}));
    // A missing file is a failure of the whole command.
    let out = Command::cargo_bin("sceneeval")
        .unwrap()
        .args(["relate", "--input", "/nonexistent/queries.jsonl"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot open"));
}

#[test]
fn every_architecture_relation_answers() {
    let names = [
        ("next_to", Some("wall")),
        ("near", Some("door")),
        ("across_from", Some("window")),
        ("far", Some("wall")),
        ("inside_room", None),
        ("middle_of_room", None),
        ("corner_of_room", None),
        ("on_wall", None),
        ("against_wall", None),
        ("hang_from_ceiling", None),
    ];
    let target = r#"{"center":[2.0,2.5,0.5],"half_size":[0.5,0.5,0.5],"yaw":0.4}"#;
    let lines: Vec<String> = names
        .iter()
        .map(|(n, arch)| {
            let arch = arch.map(|a| format!(r#","arch":"{a}""#)).unwrap_or_default();
            format!(
                r#"{{"id":"{n}","relation":"{n}"{arch},"target":{target},"room":{}}}"#,
                one_line(ROOM)
            )
        })
        .collect();
    let (code, answers) = relate(&[], &lines.join("\n"));
    assert_eq!(code, 0, "{answers:?}");
    for (a, (n, _)) in answers.iter().zip(names) {
        assert_eq!(a["id"], n);
        let s = score(a);
        assert!((0.0..=1.0).contains(&s), "{n}: {s}");
    }
    // A cube in the middle of the room: inside, in the middle (the room's centroid is (2, 2.5)).
    assert_eq!(answers[4]["score"], 1.0);
    assert_eq!(answers[5]["score"], 1.0);
}

fn fixture_assets() -> String {
    format!(
        "fixture={}",
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../fixtures/assets")
            .display()
    )
}

#[test]
fn declared_objects_and_rooms_answer_as_inline_ones_in_input_order() {
    let room = one_line(ROOM);
    let stand = r#"{"center":[-1.05,0.5,0.3],"half_size":[0.25,0.2,0.3],"yaw":1.5707963267948966}"#;
    let lines = [
        format!(r#"{{"id":"d1","declare":"bed","object":{BED}}}"#),
        format!(r#"{{"id":"d2","declare":"stand","object":{stand}}}"#),
        format!(r#"{{"id":"d3","declare":"bedroom","room":{room}}}"#),
        // Inline, by name, and mixed.
        format!(r#"{{"id":1,"relation":"side_of","side":"left","target":{stand},"anchor":{BED}}}"#),
        r#"{"id":2,"relation":"side_of","side":"left","target":"stand","anchor":"bed"}"#.to_owned(),
        format!(r#"{{"id":3,"relation":"side_of","side":"left","target":"stand","anchor":{BED}}}"#),
        format!(r#"{{"id":4,"relation":"near","arch":"door","target":{BED},"room":{room}}}"#),
        r#"{"id":5,"relation":"near","arch":"door","target":"bed","room":"bedroom"}"#.to_owned(),
        format!(r#"{{"id":6,"relation":"surround","anchor":{BED},"targets":["stand",{stand},"stand"]}}"#),
        r#"{"id":7,"relation":"surround","anchor":"bed","targets":["stand","stand","stand"]}"#.to_owned(),
    ];
    let (code, answers) = relate(&[], &lines.join("\n"));
    assert_eq!(code, 0, "{answers:?}");
    assert_eq!(answers.len(), lines.len());
    assert_eq!(answers[0], json!({"id": "d1", "declared": "bed"}));
    assert_eq!(answers[1], json!({"id": "d2", "declared": "stand"}));
    assert_eq!(answers[2], json!({"id": "d3", "declared": "bedroom"}));
    for (i, a) in answers[3..].iter().enumerate() {
        assert_eq!(a["id"], i + 1, "answers in input order");
    }
    // The nightstand wholly beyond the bed's -x face (see the_four_forms_of_the_issue).
    for a in &answers[3..6] {
        assert_eq!(a["score"], 1.0, "{a}");
    }
    assert_eq!(
        answers[6],
        json!({"id": 4, "score": answers[7]["score"], "holds": answers[7]["holds"]})
    );
    assert_eq!(answers[8]["score"], answers[9]["score"]);
}

#[test]
fn unknown_names_failed_declarations_and_redeclarations() {
    let room = one_line(ROOM);
    let near = |id: &str, target: &str| {
        format!(r#"{{"id":"{id}","relation":"near","target":{target},"anchor":"bed"}}"#)
    };
    let lines = [
        // 1: before any declaration.
        near("early", r#""stand""#),
        format!(r#"{{"id":"d","declare":"bed","object":{BED}}}"#),
        // 3: the box 2 m from the bed's centre: a 1.0 m gap, inside near's range.
        near("q1", r#"{"center":[2.0,0,0.3],"half_size":[0.2,0.2,0.3],"yaw":0}"#),
        // 4: the bed moved 10 m away: declaring it again replaces it.
        r#"{"id":"move","declare":"bed","object":{"center":[12,0,0.3],"half_size":[0.8,1.0,0.3]}}"#.to_owned(),
        near("q2", r#"{"center":[2.0,0,0.3],"half_size":[0.2,0.2,0.3],"yaw":0}"#),
        // 6: a name keeps its kind.
        format!(r#"{{"id":"kind","declare":"bed","room":{room}}}"#),
        // 7: a failed declaration leaves the name unusable.
        r#"{"id":"broken","declare":"bed","object":{"center":[0,0,0],"half_size":[-1,1,1]}}"#.to_owned(),
        near("q3", r#"{"center":[2.0,0,0.3],"half_size":[0.2,0.2,0.3],"yaw":0}"#),
        // 9: an object where a room is expected, and the reverse.
        format!(r#"{{"id":"r","declare":"bedroom","room":{room}}}"#),
        r#"{"id":"swap","relation":"inside_room","target":"bedroom","room":"bedroom"}"#.to_owned(),
        r#"{"id":"noroom","relation":"inside_room","target":{"center":[1,1,0.5],"half_size":[0.5,0.5,0.5]},"room":"kitchen"}"#.to_owned(),
        // 12: declarations carry nothing of a query; references are not declarations.
        r#"{"id":"mixed","declare":"x","object":{"center":[0,0,0],"half_size":[1,1,1]},"relation":"near"}"#.to_owned(),
        r#"{"id":"alias","declare":"y","object":"bedroom"}"#.to_owned(),
        r#"{"id":"nothing","declare":"z"}"#.to_owned(),
    ];
    let (code, answers) = relate(&[], &lines.join("\n"));
    assert_eq!(code, 2);
    assert_eq!(answers.len(), lines.len());
    let error = |i: usize| answers[i]["error"].as_str().unwrap_or_default().to_owned();
    assert!(
        error(0).contains(r#"no object named "stand" has been declared"#),
        "{}",
        error(0)
    );
    assert!(error(0).starts_with("line 1: "), "{}", error(0));
    assert_eq!(answers[2], json!({"id": "q1", "score": 1.0, "holds": true}));
    assert_eq!(answers[3], json!({"id": "move", "declared": "bed"}));
    // 12 m away: a gap of 12 - 2 - 0.8 - 0.2 = 9 m, far outside near's range.
    assert_eq!(answers[4]["holds"], false, "{}", answers[4]);
    assert!(error(5).contains("declared as an object"), "{}", error(5));
    assert!(
        error(6).contains(r#"declaration of "bed""#) && error(6).contains("not a valid box"),
        "{}",
        error(6)
    );
    assert!(
        error(7).contains("its declaration on line 7 failed"),
        "{}",
        error(7)
    );
    assert_eq!(answers[8]["declared"], "bedroom");
    assert!(error(9).contains("is a room, not an object"), "{}", error(9));
    assert!(error(10).contains(r#"no room named "kitchen""#), "{}", error(10));
    assert!(error(11).contains("not \"relation\""), "{}", error(11));
    assert!(error(12).contains("written in place"), "{}", error(12));
    assert!(
        error(13).contains("needs \"object\" or \"room\""),
        "{}",
        error(13)
    );
}

#[test]
fn mesh_objects_from_assets_score_as_the_library_scores_them() {
    use sceneeval::geom::{Vector3, conventions::pose_from_yaw};
    use sceneeval::io::AssetLibrary;
    use sceneeval::relations::{ObjectGeom, Relation, RelationParams, batch};

    let assets = fixture_assets();
    // A nightstand (box) 5 cm left of the bed's bounds (x in [1.2, 2.8] for the 1.6 m wide
    // bed at x = 2), and the desk chair asset near the bed's foot.
    let bed = r#"{"asset":"fixture.bed","position":[2.0,2.5,0.0],"yaw":0.0}"#;
    let stand = r#"{"center":[0.925,2.5,0.275],"half_size":[0.225,0.21,0.275],"yaw":0}"#;
    let chair = r#"{"asset":"fixture.chair","position":[2.3,0.6,0.0],"yaw":3.0,"scale":1.1}"#;
    let relations = [
        "side_of(left)",
        "next_to",
        "near",
        "far",
        "face_to",
        "across_from",
        "inside_of",
    ];
    let mut lines = vec![format!(r#"{{"declare":"bed","object":{bed}}}"#)];
    for r in relations {
        lines.push(format!(r#"{{"relation":"{r}","target":{stand},"anchor":"bed"}}"#));
        lines.push(format!(r#"{{"relation":"{r}","target":{chair},"anchor":{bed}}}"#));
    }
    let (code, answers) = relate(&["--assets", &assets], &lines.join("\n"));
    assert_eq!(code, 0, "{answers:?}");
    assert_eq!(answers[0]["declared"], "bed");
    // The same objects through the library.
    let library = AssetLibrary::from_specs(&[&assets]).unwrap();
    let bed = library
        .object(
            "bed",
            "fixture.bed",
            pose_from_yaw([2.0, 2.5, 0.0].into(), 0.0),
            Vector3::repeat(1.0),
        )
        .unwrap();
    let chair = library
        .object(
            "chair",
            "fixture.chair",
            pose_from_yaw([2.3, 0.6, 0.0].into(), 3.0),
            Vector3::repeat(1.1),
        )
        .unwrap();
    let stand =
        sceneeval::geom::Obb::from_yaw([0.925, 2.5, 0.275].into(), Vector3::new(0.225, 0.21, 0.275), 0.0)
            .unwrap();
    let p = RelationParams::default();
    for (k, r) in relations.iter().enumerate() {
        let relation: Relation = r.parse().unwrap();
        let by_stand = batch::score_pair(
            relation,
            &ObjectGeom::from_box(&stand),
            &ObjectGeom::from_object(&bed),
            &p,
        )
        .unwrap();
        let by_chair = batch::score_pair(
            relation,
            &ObjectGeom::from_object(&chair),
            &ObjectGeom::from_object(&bed),
            &p,
        )
        .unwrap();
        assert_eq!(
            score(&answers[1 + 2 * k]).to_bits(),
            by_stand.to_bits(),
            "{r} stand"
        );
        assert_eq!(
            score(&answers[2 + 2 * k]).to_bits(),
            by_chair.to_bits(),
            "{r} chair"
        );
    }
    // The nightstand lies wholly beyond the bed's -x face.
    assert_eq!(score(&answers[1]), 1.0);
    // Asset errors name the object and the asset; without --assets no prefix is known.
    let lines = [
        r#"{"id":1,"declare":"x","object":{"asset":"fixture.unicorn","position":[0,0,0]}}"#,
        r#"{"id":2,"relation":"near","target":{"asset":"nowhere.bed","position":[0,0,0]},"anchor":{"center":[0,0,0],"half_size":[1,1,1]}}"#,
        r#"{"id":3,"relation":"near","target":{"asset":"fixture.bed","position":[0,0,0],"scale":0},"anchor":{"center":[0,0,0],"half_size":[1,1,1]}}"#,
    ];
    let (code, answers) = relate(&["--assets", &assets], &lines.join("\n"));
    assert_eq!(code, 2);
    let error = |i: usize| answers[i]["error"].as_str().unwrap().to_owned();
    assert!(error(0).contains("fixture.unicorn"), "{}", error(0));
    assert!(error(1).contains("nowhere"), "{}", error(1));
    assert!(error(2).contains("scale"), "{}", error(2));
    let (_, answers) = relate(&[], lines[1]);
    assert!(answers[0]["error"].as_str().unwrap().contains("nowhere"));
}

#[test]
fn a_pipe_client_gets_each_answer_while_it_waits() {
    use std::io::{BufRead, BufReader, Write};
    use std::process::{Command as Std, Stdio};
    use std::sync::mpsc;
    use std::time::Duration;

    let mut child = Std::new(assert_cmd::cargo::cargo_bin("sceneeval"))
        .arg("relate")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let stdout = child.stdout.take().unwrap();
    let (send, receive) = mpsc::channel();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            if send.send(line.unwrap()).is_err() {
                break;
            }
        }
    });
    // A generous timeout: only a missing flush would make it expire (the process waits for
    // more input with the answer unsent); no speed is asserted.
    let wait = Duration::from_secs(120);
    let declare = format!(r#"{{"id":"d","declare":"bed","object":{BED}}}"#);
    let query = r#"{"id":"q","relation":"near","target":{"center":[2.0,0,0.3],"half_size":[0.2,0.2,0.3],"yaw":0},"anchor":"bed"}"#;
    for (line, expected) in [
        (declare.as_str(), json!({"id": "d", "declared": "bed"})),
        (query, json!({"id": "q", "score": 1.0, "holds": true})),
    ] {
        writeln!(stdin, "{line}").unwrap();
        stdin.flush().unwrap();
        let answer = receive
            .recv_timeout(wait)
            .expect("an answer while the client waits");
        assert_eq!(serde_json::from_str::<Value>(&answer).unwrap(), expected);
    }
    drop(stdin);
    assert!(child.wait().unwrap().success());
    reader.join().unwrap();
}
