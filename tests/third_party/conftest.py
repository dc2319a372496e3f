"""Third-party code vendored for the tests: never collected or imported as tests (its modules
import ``rospy``; ``client_test.py`` runs on import). The tests that drive it live beside the
code they test (tests/api/armor/test_armor_py_api.py)."""

collect_ignore = ["armor_py_api", "rospy_over_http"]
