"""ARMOR directive sequences for the ROS tests: every command family, and armor_py_api's own
test script (``scripts/armor_api/client_test.py``) as the directives it sends."""

from pathlib import Path

from tests.api.armor.conftest import DATA, TEST_IRI, Step


def every_family(saved: Path) -> list[Step]:
    """Load, manipulate, query, reason, save, log, mount, the memory, and refused directives."""
    owl = str(DATA / "test.owl")
    return [
        ("LOAD", "FILE", "", [owl, TEST_IRI, "true", "PELLET", "true"]),
        ("MOUNT", "", "", []),
        ("ADD", "IND", "CLASS", ["ind_1", "Class_1"]),
        ("ADD", "IND", "CLASS", ["ind_2", "Class_2"]),
        ("ADD", "IND", "CLASS", ["ind_3", "Class_3"]),
        ("ADD", "OBJECTPROP", "IND", ["OProperty_1", "ind_1", "ind_3"]),
        ("ADD", "DATAPROP", "IND", ["DProperty_1", "ind_1", "INTEGER", "1"]),
        ("REPLACE", "DATAPROP", "IND", ["DProperty_1", "ind_1", "INTEGER", "3", "1"]),
        ("ADD", "CLASS", "CLASS", ["Class_5", "Class_1"]),
        ("DISJOINT", "IND", "", ["ind_2", "ind_3"]),
        ("APPLY", "", "", []),
        ("REASON", "", "", []),
        ("QUERY", "IND", "CLASS", ["Class_4"]),
        ("QUERY", "IND", "", ["ind_1"]),
        ("QUERY", "DATAPROP", "IND", ["DProperty_1", "ind_1"]),
        ("QUERY", "OBJECTPROP", "IND", ["OProperty_1", "ind_1"]),
        ("QUERY", "CLASS", "CLASS", ["Class_1"]),
        ("QUERY", "IND", "", ["ind_missing"]),
        ("QUERY", "SPARQL", "", ["SELECT ?s WHERE { ?s a <" + TEST_IRI + "#Class_1> }"]),
        ("QUERY", "CLASS", "IND", ["ind_1", "true"]),
        ("QUERY", "IND", "DATAPROP", ["ind_1"]),
        ("QUERY", "IND", "OBJECTPROP", ["ind_1"]),
        ("ADD", "CARDINALITY", "MIN", ["Class_6", "OProperty_1", "2", "Class_3"]),
        ("MAKE", "EQUIVALENT", "CLASS", ["Class_6"]),
        ("QUERY", "CLASS", "RESTRICTIONS", ["Class_6"]),
        ("DISJOINT", "CLASS", "", ["Class_2", "Class_3"]),
        ("SAVE", "INFERENCE", "", [str(saved) + ".inferred"]),
        ("REMOVE", "DATAPROP", "IND", ["DProperty_1", "ind_1", "INTEGER", "3"]),
        ("RENAME", "IND", "", ["ind_2", "ind_two"]),
        ("RENAME", "CLASS", "", ["Class_5", "Class_five"]),
        ("REMOVE", "CLASS", "CLASS", ["Class_five", "Class_1"]),
        ("REMOVE", "IND", "CLASS", ["ind_3", "Class_3"]),
        ("APPLY", "", "", []),
        ("SAVE", "", "", [str(saved)]),
        ("LOG", "SCREEN", "ON", []),
        ("LOG", "SCREEN", "OFF", []),
        ("GET", "ALL", "REFS", []),
        ("GET", "REF", "CLIENT", []),
        ("UNMOUNT", "", "", []),
        ("ADD", "IND", "CLASS", ["ind_4"]),  # too few arguments
        ("ADD", "IND", "CLASS", ["ind_4", "Class_1", "extra", "more"]),
        ("FLY", "", "", []),  # no such command
        ("DROP", "", "", []),
        ("QUERY", "IND", "CLASS", ["Class_1"]),  # the reference was dropped
    ]


def armor_py_api_client_test() -> list[Step]:
    """What armor_py_api's client_test.py sends, in order (its calls written as directives)."""
    owl = str(DATA / "test.owl")
    return [
        # client.utils.load_ref_from_file(path, iri, True, "PELLET", True, False)
        ("LOAD", "FILE", "", [owl, TEST_IRI, "true", "PELLET", "true"]),
        ("MOUNT", "", "", []),  # utils.mount_on_ref()
        ("LOG", "SCREEN", "ON", []),  # utils.set_log_to_terminal(True)
        ("ADD", "IND", "CLASS", ["ind_1", "Class_1"]),  # manipulation.add_ind_to_class
        ("ADD", "IND", "CLASS", ["ind_2", "Class_2"]),
        ("ADD", "IND", "CLASS", ["ind_3", "Class_3"]),
        ("ADD", "OBJECTPROP", "IND", ["OProperty_1", "ind_1", "ind_3"]),
        ("ADD", "OBJECTPROP", "IND", ["OProperty_2", "ind_1", "ind_2"]),
        ("ADD", "DATAPROP", "IND", ["DProperty_1", "ind_1", "INTEGER", "1"]),
        ("REPLACE", "DATAPROP", "IND", ["DProperty_1", "ind_1", "INTEGER", "3", "1"]),
        ("APPLY", "", "", []),  # utils.apply_buffered_changes()
        ("REASON", "", "", []),  # utils.sync_buffered_reasoner()
        ("QUERY", "IND", "", ["ind_1"]),  # query.check_ind_exists("ind_1")
    ]
