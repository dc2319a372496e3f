"""Every command of ARMOR's table through the real server: success and each error path."""

from collections.abc import Callable

import pytest

from tests.api.armor.conftest import Armor

EX = "http://ex.org/"


def test_add_then_query_returns_armor_strings(armor: Armor, loaded: Callable[..., str]) -> None:
    ref = loaded()
    assert armor.call("ADD", "IND", "CLASS", ["ind_1", "Class_1"], ref=ref)["success"]
    assert armor.call("ADD", "CLASS", "CLASS", ["Class_1", "Class_0"], ref=ref)["success"]
    result = armor.call("QUERY", "IND", "", ["ind_1"], ref=ref)
    assert result["success"] and result["exit_code"] == 0
    assert set(result["queried_objects"]) == {f"<{EX}{ref}#Class_1>", f"<{EX}{ref}#Class_0>"}
    assert armor.call("QUERY", "IND", "CLASS", ["Class_0"], ref=ref)["queried_objects"] == [
        f"<{EX}{ref}#ind_1>"
    ]


def test_query_ind_of_a_missing_individual_is_success_false_with_code_0(
    armor: Armor, loaded: Callable[..., str]
) -> None:
    ref = loaded()
    armor.call("ADD", "IND", "", ["only_thing"], ref=ref)
    for name in ("nobody", "only_thing"):
        result = armor.call("QUERY", "IND", "", [name], ref=ref)
        assert (result["success"], result["exit_code"], result["queried_objects"]) == (False, 0, [])


def test_data_properties_keep_armor_types(armor: Armor, loaded: Callable[..., str]) -> None:
    ref = loaded()
    for prop, kind, value in [
        ("count", "INTEGER", "3"),
        ("stamp", "LONG", "1665579740"),
        ("ratio", "DOUBLE", "0.5"),
        ("name", "STRING", 'say "hi"'),
        ("ok", "BOOLEAN", "True"),
    ]:
        assert (
            armor.call("ADD", "DATAPROP", "IND", [prop, "r", kind, value], ref=ref)["exit_code"]
            == 0
        )
    got = {
        prop: armor.call("QUERY", "DATAPROP", "IND", [prop, "r"], ref=ref)["queried_objects"]
        for prop in ("count", "stamp", "ratio", "name", "ok")
    }
    assert got == {
        "count": ['"3"^^xsd:integer'],
        "stamp": ['"1665579740"^^xsd:long'],
        "ratio": ['"0.5"^^xsd:float'],
        "name": ['"say \\"hi\\""^^xsd:string'],
        "ok": ['"true"^^xsd:boolean'],
    }
    plain = armor.call("QUERY", "DATAPROP", "IND", ["stamp", "r"], ref=ref, values="plain")
    assert plain["queried_objects"] == ["1665579740"]
    short = armor.call("QUERY", "IND", "DATAPROP", ["r"], ref=ref, values="short")
    assert sorted(short["queried_objects"]) == ["count", "name", "ok", "ratio", "stamp"]


@pytest.mark.parametrize(
    ("command", "args", "success"),
    [
        (("ADD", "DATAPROP", "IND"), ["p", "i", "COMPLEX", "1"], True),
        (("REMOVE", "DATAPROP", "IND"), ["p", "i", "COMPLEX", "1"], True),
        (("REPLACE", "DATAPROP", "IND"), ["p", "i", "COMPLEX", "1", "0"], False),
    ],
)
def test_unknown_value_type_answers_101(
    armor: Armor,
    loaded: Callable[..., str],
    command: tuple[str, str, str],
    args: list[str],
    success: bool,
) -> None:
    ref = loaded()
    result = armor.call(*command, args, ref=ref)
    assert (result["success"], result["exit_code"]) == (success, 101)
    assert "Value type COMPLEX not supported" in result["error_description"]
    assert armor.call("QUERY", "DATAPROP", "IND", ["p", "i"], ref=ref)["queried_objects"] == []


def test_object_properties_replace_and_remove(armor: Armor, loaded: Callable[..., str]) -> None:
    ref = loaded()
    armor.call("ADD", "OBJECTPROP", "IND", ["isIn", "robot", "kitchen"], ref=ref)
    armor.call("REPLACE", "OBJECTPROP", "IND", ["isIn", "robot", "hall", "kitchen"], ref=ref)
    assert armor.call("QUERY", "OBJECTPROP", "IND", ["isIn", "robot"], ref=ref)[
        "queried_objects"
    ] == [f"<{EX}{ref}#hall>"]
    assert armor.call("QUERY", "IND", "OBJECTPROP", ["robot"], ref=ref)["queried_objects"] == [
        f"<{EX}{ref}#isIn>"
    ]
    armor.call("REMOVE", "OBJECTPROP", "IND", ["isIn", "robot", "hall"], ref=ref)
    assert (
        armor.call("QUERY", "OBJECTPROP", "IND", ["isIn", "robot"], ref=ref)["queried_objects"]
        == []
    )


def test_replace_and_remove_data_property(armor: Armor, loaded: Callable[..., str]) -> None:
    ref = loaded()
    armor.call("ADD", "DATAPROP", "IND", ["now", "robot", "LONG", "10"], ref=ref)
    armor.call("REPLACE", "DATAPROP", "IND", ["now", "robot", "LONG", "20", "10"], ref=ref)
    assert armor.call("QUERY", "DATAPROP", "IND", ["now", "robot"], ref=ref)["queried_objects"] == [
        '"20"^^xsd:long'
    ]
    armor.call("REMOVE", "DATAPROP", "IND", ["now", "robot", "LONG", "20"], ref=ref)
    assert (
        armor.call("QUERY", "DATAPROP", "IND", ["now", "robot"], ref=ref)["queried_objects"] == []
    )


def test_class_hierarchy_queries(armor: Armor, loaded: Callable[..., str]) -> None:
    ref = loaded()
    armor.call("ADD", "CLASS", "", ["Location"], ref=ref)
    armor.call("ADD", "CLASS", "CLASS", ["Room", "Location"], ref=ref)
    armor.call("ADD", "CLASS", "CLASS", ["Corridor", "Location"], ref=ref)
    armor.call("ADD", "CLASS", "CLASS", ["Kitchen", "Room"], ref=ref)
    armor.call("ADD", "IND", "CLASS", ["k1", "Kitchen"], ref=ref)
    subs = armor.call("QUERY", "CLASS", "CLASS", ["Location"], ref=ref, values="short")[
        "queried_objects"
    ]
    assert sorted(subs) == ["Corridor", "Kitchen", "Nothing", "Room"]
    assert armor.call("QUERY", "CLASS", "IND", ["k1", "true"], ref=ref)["queried_objects"] == [
        "Kitchen"
    ]
    assert sorted(
        armor.call("QUERY", "CLASS", "IND", ["k1"], ref=ref, values="short")["queried_objects"]
    ) == [
        "Kitchen",
        "Location",
        "Room",
    ]
    armor.call("REMOVE", "CLASS", "CLASS", ["Kitchen", "Room"], ref=ref)
    assert armor.call("QUERY", "CLASS", "IND", ["k1", "false"], ref=ref, values="short")[
        "queried_objects"
    ] == ["Kitchen"]
    armor.call("REMOVE", "IND", "CLASS", ["k1", "Kitchen"], ref=ref)
    assert not armor.call("QUERY", "IND", "", ["k1"], ref=ref)["success"]
    armor.call("REMOVE", "CLASS", "", ["Location"], ref=ref)
    sparql = (
        "SELECT ?s WHERE { ?s <http://www.w3.org/2000/01/rdf-schema#subClassOf> "
        "<http://www.w3.org/2002/07/owl#Thing> }"
    )
    assert armor.call("QUERY", "SPARQL", "", [sparql], ref=ref)["queried_objects"] == [""]


def test_disjoint_variants_write_owl(armor: Armor, loaded: Callable[..., str]) -> None:
    ref = loaded()
    for ind in ("a", "b", "c"):
        armor.call("ADD", "IND", "CLASS", [ind, "Room"], ref=ref)
    armor.call("ADD", "CLASS", "CLASS", ["Kitchen", "Room"], ref=ref)
    armor.call("ADD", "CLASS", "CLASS", ["Hall", "Room"], ref=ref)
    assert armor.call("DISJOINT", "IND", "", ["a", "b"], ref=ref)["success"]
    assert armor.call("DISJOINT", "IND", "CLASS", ["Room"], ref=ref)["success"]
    assert armor.call("DISJOINT", "CLASS", "", ["X", "Y", "Z"], ref=ref)["success"]
    assert armor.call("DISJOINT", "CLASS", "CLASS", ["Room"], ref=ref)["success"]
    count = "SELECT (COUNT(*) AS ?n) WHERE { ?x a <http://www.w3.org/2002/07/owl#%s> }"
    assert armor.call("QUERY", "SPARQL", "", [count % "AllDifferent"], ref=ref)[
        "queried_objects"
    ] == ["{n=1^^http://www.w3.org/2001/XMLSchema#integer}"]
    assert armor.call("QUERY", "SPARQL", "", [count % "AllDisjointClasses"], ref=ref)[
        "queried_objects"
    ] == ["{n=1^^http://www.w3.org/2001/XMLSchema#integer}"]
    pair = "SELECT ?a ?b WHERE { ?a <http://www.w3.org/2002/07/owl#disjointWith> ?b }"
    assert armor.call("QUERY", "SPARQL", "", [pair], ref=ref, values="short")[
        "queried_objects"
    ] == ["{a=Hall, b=Kitchen}"]
    one = armor.call("DISJOINT", "IND", "", ["a"], ref=ref)
    assert (one["success"], one["exit_code"]) == (False, 208)


def test_cardinality_restrictions_and_make_equivalent(
    armor: Armor, loaded: Callable[..., str]
) -> None:
    ref = loaded()
    for key in (("ADD", "CARDINALITY", "MIN"), ("ADD", "MIN", "CARDINALITY")):
        assert armor.call(*key, ["Stack", "hasPart", "2", "Box"], ref=ref)["success"]
    restrictions = armor.call("QUERY", "CLASS", "RESTRICTIONS", ["Stack"], ref=ref)[
        "queried_objects"
    ]
    assert restrictions == ["[MIN : Stack -> hasPart 2(Box)]"]
    bad = armor.call("ADD", "CARDINALITY", "MIN", ["Stack", "hasPart", "two", "Box"], ref=ref)
    assert (bad["success"], bad["exit_code"]) == (False, 208)
    armor.call("ADD", "CLASS", "CLASS", ["Stack", "Thing_on_table"], ref=ref)
    assert armor.call("MAKE", "EQUIVALENT", "CLASS", ["Stack"], ref=ref)["success"]
    ask = (
        "SELECT ?c WHERE { ?c <http://www.w3.org/2002/07/owl#equivalentClass> ?x . "
        "?x <http://www.w3.org/2002/07/owl#intersectionOf> ?l }"
    )
    assert armor.call("QUERY", "SPARQL", "", [ask], ref=ref, values="short")["queried_objects"] == [
        "{c=Stack}"
    ]
    subclass = "SELECT ?x WHERE { ?c <http://www.w3.org/2000/01/rdf-schema#subClassOf> ?x }"
    assert armor.call("QUERY", "SPARQL", "", [subclass], ref=ref)["queried_objects"] == [""]


def test_remove_ind_removes_every_axiom_mentioning_it(
    armor: Armor, loaded: Callable[..., str]
) -> None:
    ref = loaded()
    armor.call("ADD", "IND", "CLASS", ["b", "Box"], ref=ref)
    armor.call("ADD", "OBJECTPROP", "IND", ["on", "a", "b"], ref=ref)
    armor.call("DISJOINT", "IND", "", ["a", "b", "c"], ref=ref)
    assert armor.call("REMOVE", "IND", "", ["b"], ref=ref)["success"]
    mention = (
        f"SELECT ?s ?p ?o WHERE {{ ?s ?p ?o FILTER(?s = <{EX}{ref}#b> || ?o = <{EX}{ref}#b>) }}"
    )
    assert armor.call("QUERY", "SPARQL", "", [mention], ref=ref)["queried_objects"] == [""]
    lists = "SELECT ?x WHERE { ?x a <http://www.w3.org/2002/07/owl#AllDifferent> }"
    assert armor.call("QUERY", "SPARQL", "", [lists], ref=ref)["queried_objects"] == [""]
    assert (
        armor.call("QUERY", "IND", "", ["a"], ref=ref)["success"] is False
    )  # only owl:NamedIndividual left


@pytest.mark.parametrize("kind", ["IND", "CLASS", "DATAPROP", "OBJECTPROP"])
def test_rename_moves_every_triple(armor: Armor, loaded: Callable[..., str], kind: str) -> None:
    ref = loaded()
    armor.call("ADD", "IND", "CLASS", ["old_ind", "OldClass"], ref=ref)
    armor.call("ADD", "DATAPROP", "IND", ["old_dp", "old_ind", "INTEGER", "1"], ref=ref)
    armor.call("ADD", "OBJECTPROP", "IND", ["old_op", "old_ind", "x"], ref=ref)
    old = {"IND": "old_ind", "CLASS": "OldClass", "DATAPROP": "old_dp", "OBJECTPROP": "old_op"}[
        kind
    ]
    assert armor.call("RENAME", kind, "", [old, "renamed"], ref=ref)["success"]
    text = f"SELECT (COUNT(*) AS ?n) WHERE {{ ?s ?p ?o FILTER(<{EX}{ref}#%s> IN (?s, ?p, ?o)) }}"
    count = armor.call("QUERY", "SPARQL", "FORMATTED", [text % old], ref=ref, values="plain")
    assert count["sparql_queried_objects"] == [{"key": "n", "value": "0"}]
    count = armor.call("QUERY", "SPARQL", "FORMATTED", [text % "renamed"], ref=ref, values="plain")
    assert int(count["sparql_queried_objects"][0]["value"]) >= 1


def test_sparql_argument_forms_and_formats(armor: Armor, loaded: Callable[..., str]) -> None:
    ref = loaded()
    armor.call("ADD", "DATAPROP", "IND", ["size", "a", "INTEGER", "3"], ref=ref)
    armor.call("ADD", "DATAPROP", "IND", ["label", "a", "STRING", "box [1]"], ref=ref)
    prefix, select, where = f"PREFIX : <{EX}{ref}#> ", "SELECT ?s ?v ", "WHERE { ?s :size ?v }"
    expected = [f"{{s={EX}{ref}#a, v=3^^http://www.w3.org/2001/XMLSchema#integer}}"]
    for args in (
        [prefix + select + where],
        [prefix + select + where, "5000"],
        [prefix, select, where],
        [prefix, select, where, "5000"],
    ):
        assert armor.call("QUERY", "SPARQL", "", args, ref=ref)["queried_objects"] == expected
    formatted = armor.call("QUERY", "SPARQL", "FORMATTED", [prefix, select, where], ref=ref)
    assert formatted["queried_objects"] == []
    assert formatted["sparql_queried_objects"] == [
        {"key": "s", "value": f"{EX}{ref}#a"},
        {"key": "v", "value": "3^^http://www.w3.org/2001/XMLSchema#integer"},
    ]
    label = armor.call(
        "QUERY", "SPARQL", "", [f"SELECT ?v WHERE {{ ?s <{EX}{ref}#label> ?v }}"], ref=ref
    )
    assert label["queried_objects"] == ["{v=box 1}"]  # Java's toString with every bracket removed


@pytest.mark.parametrize(
    ("args", "code", "fragment"),
    [
        (["SELECT ?s WHERE { ?s ?p }"], 210, "SPARQL"),
        (["ASK { ?s ?p ?o }"], 210, "SELECT"),
        (["SELECT * WHERE { SERVICE <http://x/> { ?s ?p ?o } }"], 210, "SERVICE"),
        (["SELECT * WHERE { ?s ?p ?o }", "soon"], 208, "milliseconds"),
        (["a", "b", "c", "d", "e"], 208, "expected [query]"),
    ],
)
def test_sparql_errors(
    armor: Armor, loaded: Callable[..., str], args: list[str], code: int, fragment: str
) -> None:
    ref = loaded()
    result = armor.call("QUERY", "SPARQL", "", args, ref=ref)
    assert (result["success"], result["exit_code"]) == (False, code)
    assert fragment in result["error_description"]


@pytest.mark.parametrize(
    ("request_fields", "code", "fragment"),
    [
        (
            {
                "reference_name": "",
                "command": "GET",
                "primary_command_spec": "ALL",
                "secondary_command_spec": "REFS",
            },
            201,
            "No reference name",
        ),
        ({"command": ""}, 202, "No command"),
        ({"command": "ADD ", "primary_command_spec": "IND"}, 205, "No Command/Specs combination"),
        ({"command": "SWRL"}, 205, "No Command/Specs combination"),
        (
            {"command": "ADD", "primary_command_spec": "DATAPROP"},
            205,
            "No Command/Specs combination",
        ),
        (
            {
                "reference_name": "never_loaded",
                "command": "QUERY",
                "primary_command_spec": "IND",
                "args": ["x"],
            },
            207,
            "no reference 'never_loaded'",
        ),
        ({"reference_name": "never_loaded", "command": "UNMOUNT"}, 207, "no reference"),
        (
            {
                "reference_name": "never_loaded",
                "command": "GET",
                "primary_command_spec": "REF",
                "secondary_command_spec": "CLIENT",
                "args": ["never_loaded"],
            },
            207,
            "no reference",
        ),
        (
            {
                "command": "ADD",
                "primary_command_spec": "IND",
                "secondary_command_spec": "CLASS",
                "args": ["only_one"],
            },
            208,
            "args[1] (class): missing",
        ),
        (
            {
                "command": "ADD",
                "primary_command_spec": "DATAPROP",
                "secondary_command_spec": "IND",
                "args": ["p", "i", "INTEGER", "three"],
            },
            208,
            "expected an integer",
        ),
        ({"command": "ADD", "primary_command_spec": "IND", "args": ["bad\tname"]}, 208, "IRI"),
        (
            {
                "command": "LOAD",
                "primary_command_spec": "FILE",
                "reference_name": "new_ref",
                "args": ["no/such/file.owl", "http://ex.org/x"],
            },
            209,
            "cannot read",
        ),
        (
            {
                "command": "LOAD",
                "primary_command_spec": "FILE",
                "reference_name": "new_ref2",
                "args": ["", "http://ex.org/x", "false", "RACER", "false"],
            },
            208,
            "reasoner",
        ),
        (
            {
                "command": "LOAD",
                "primary_command_spec": "FILE",
                "reference_name": "bad name",
                "args": ["", "http://ex.org/x"],
            },
            208,
            "reference_name",
        ),
        (
            {
                "command": "LOAD",
                "primary_command_spec": "WEB",
                "reference_name": "new_ref3",
                "args": ["ftp://x/y.owl", "http://ex.org/x"],
            },
            208,
            "http",
        ),
        ({"command": "SAVE", "args": [""]}, 208, "give a path"),
        (
            {"command": "LOG", "primary_command_spec": "FILE", "secondary_command_spec": "ON"},
            208,
            "args[0]",
        ),
    ],
)
def test_error_paths(
    armor: Armor,
    loaded: Callable[..., str],
    request_fields: dict[str, object],
    code: int,
    fragment: str,
) -> None:
    ref = loaded()
    body = {"client_name": "c", "reference_name": ref, **request_fields}
    response = armor.http.post("/armor_interface_srv", json={"armor_request": body})
    assert response.status_code == 200
    result = response.json()["armor_response"]
    assert (result["success"], result["exit_code"]) == (False, code), result
    assert fragment in result["error_description"]


def test_lower_case_commands_and_missing_fields(armor: Armor, loaded: Callable[..., str]) -> None:
    ref = loaded()
    assert armor.call("add", "ind", "class", ["a", "Box"], ref=ref)["success"]
    assert armor.call("Query", "Ind", "Class", ["Box"], ref=ref)["queried_objects"] == [
        f"<{EX}{ref}#a>"
    ]
    minimal = armor.http.post(
        "/armor_interface_srv", json={"armor_request": {"reference_name": ref}}
    )
    assert minimal.status_code == 200
    assert minimal.json()["armor_response"] == {
        "success": False,
        "timeout": False,
        "exit_code": 202,
        "error_description": "Invalid request. No command specified.",
        "is_consistent": False,
        "queried_objects": [],
        "sparql_queried_objects": [],
    }
    empty = armor.http.post("/armor_interface_srv", json={})
    assert empty.json()["armor_response"]["exit_code"] == 201


@pytest.mark.parametrize(
    "body",
    [
        {"armor_request": {"command": 3}},
        {"armor_request": {"args": "not a list"}},
        {"armor_request": {"args": [1, 2]}},
        {"armor_request": {"unknown_field": "x"}},
        {"armor_requests": "x"},
    ],
)
def test_malformed_bodies_answer_422_with_a_message(armor: Armor, body: dict[str, object]) -> None:
    path = "/armor_interface_serialized_srv" if "armor_requests" in body else "/armor_interface_srv"
    response = armor.http.post(path, json=body)
    assert response.status_code == 422
    assert response.json()["detail"]


def test_non_json_body_answers_422(armor: Armor) -> None:
    response = armor.http.post(
        "/armor_interface_srv", content=b"{not json", headers={"content-type": "application/json"}
    )
    assert response.status_code == 422


def test_get_refs_client_drop_and_log(armor: Armor, loaded: Callable[..., str], tmp_path) -> None:  # type: ignore[no-untyped-def]
    ref = loaded()
    assert ref in armor.call("GET", "ALL", "REFS", ref=ref)["queried_objects"]
    assert armor.call("GET", "REF", "CLIENT", [ref], ref="anything")["queried_objects"] == ["none"]
    log = tmp_path / "armor.log"
    assert armor.call("LOG", "FILE", "ON", [str(log)], ref=ref)["success"]
    armor.call("ADD", "IND", "CLASS", ["a", "B"], ref=ref)
    assert armor.call("LOG", "FILE", "OFF", ref=ref)["success"]
    assert log.exists()
    assert armor.call("LOG", "SCREEN", "ON", ref=ref)["success"]
    assert armor.call("LOG", "SCREEN", "OFF", ref=ref)["success"]
    assert armor.call("DROP", ref=ref)["success"]
    assert ref not in armor.call("GET", "ALL", "REFS", ref="x")["queried_objects"]
    assert armor.call("QUERY", "IND", "", ["a"], ref=ref)["exit_code"] == 207
