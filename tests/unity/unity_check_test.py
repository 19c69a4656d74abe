#!/usr/bin/env python3
"""cmake/unity_check.py finds what the files of one unity batch would share, and only that.

Each case writes a few .cc files into a temporary directory and checks them as one batch.
Run by ctest (unity_check_test) or by hand: python3 tests/unity/unity_check_test.py
"""

import os
import subprocess
import sys
import tempfile
import textwrap
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECK = os.path.join(ROOT, "cmake", "unity_check.py")


def run_check(*files):
    """(exit status, message) of the files as one batch, in this order."""
    with tempfile.TemporaryDirectory() as directory:
        names = []
        for index, text in enumerate(files):
            name = f"f{index}.cc"
            with open(os.path.join(directory, name), "w", encoding="utf-8") as f:
                f.write(textwrap.dedent(text))
            names.append(name)
        done = subprocess.run([sys.executable, CHECK, "--files", directory, *names],
                              capture_output=True, text=True, check=False)
        return done.returncode, done.stderr


class UnityCheckTest(unittest.TestCase):
    def assertClash(self, name, *files):
        status, message = run_check(*files)
        self.assertEqual(status, 1, message)
        self.assertIn(name, message)
        self.assertIn("cmake/unity_alone.txt", message)  # the fix is named

    def assertClean(self, *files):
        status, message = run_check(*files)
        self.assertEqual(status, 0, message)

    def test_anonymous_helpers_of_one_signature(self):
        helper = "namespace mbstream {\nnamespace {\ndouble Seconds(int n) { return n; }\n}\n}\n"
        self.assertClash("'Seconds'", helper, helper)

    def test_anonymous_overloads_that_would_join(self):
        self.assertClash("'Seconds'",
                         "namespace mbstream { namespace { double Seconds(int n) { return n; } } }",
                         "namespace mbstream { namespace { double Seconds(long n) { return n; } } }")

    def test_static_functions_and_const_variables(self):
        self.assertClash("'Pretty'", "static int Pretty() { return 1; }", "static int Pretty() { return 2; }")
        self.assertClash("'kMaxBatch'", "namespace a { constexpr int kMaxBatch = 8; }",
                         "namespace a { const int kMaxBatch = 9; }")

    def test_types_and_aliases(self):
        self.assertClash("'Tally'", "namespace { struct Tally { int n; }; }",
                         "namespace { struct Tally { double n; }; }")
        self.assertClash("'Stream'", "namespace { using Stream = int; }", "namespace { using Stream = long; }")

    def test_the_same_alias_or_using_declaration_is_harmless(self):
        same = """\
            namespace mbstream {
            namespace fs = std::filesystem;
            using ::testing::HasSubstr;
            namespace {
            using Clock = std::chrono::steady_clock;
            }
            }
            """
        self.assertClean(same, same)

    def test_functions_of_one_name_in_nested_namespaces(self):
        self.assertClash("'Rnea'", "namespace mbstream { void Rnea(const Model& m) {} }",
                         "namespace mbstream::free_tree { void Rnea(const Model& m, int k) {} }")

    def test_a_helper_that_hides_what_a_later_file_uses(self):
        self.assertClash("'Model'", "namespace mbstream { namespace { std::string Model() { return {}; } } }",
                         "namespace mbstream { int Count(const Model& model) { return model.n; } }")
        # A member call or a qualified name is looked up elsewhere.
        self.assertClean("namespace mbstream { namespace { int Evaluate(int x) { return x; } } }",
                         "namespace mbstream { int F(J& j) { return j.Evaluate(1) + j->Evaluate(2) + b::Evaluate(3); } }")

    def test_using_directives_that_reach_later_files(self):
        directive = "namespace mbstream { using namespace testing; }\n"
        self.assertClash("using namespace testing", directive, "namespace mbstream { int x() { return 1; } }")
        self.assertClean(directive, directive)  # every later file has it already

    def test_macros_that_reach_later_files(self):
        self.assertClash("macro SKIP_UNLESS", "#define SKIP_UNLESS(x) if (!(x)) return\n",
                         "void F() { SKIP_UNLESS(true); }")
        self.assertClean("#define SKIP_UNLESS(x) if (!(x)) return\n#undef SKIP_UNLESS\n",
                         "void F() { SKIP_UNLESS(true); }")

    def test_ordinary_files_pass(self):
        first = """\
            // A comment with namespace { int Seconds; } in it, and "a string { with braces".
            #include <string>
            namespace mbstream {
            namespace {
            constexpr char kText[] = R"(raw { text } "quoted")";
            struct Fixture : public ::testing::Test {
              void SetUp() override { value = {1, 2}; }
              std::vector<int> value;
            };
            const auto kSquare = [](int x) { return x * x; };
            int Use(Options options = {}) { return options.n; }
            }  // namespace
            TEST_F(Fixture, Works) { EXPECT_EQ(kSquare(2), 4); }
            Runner::Runner(int n) : n_{n}, m_(n) {}
            int Runner::Run() const { return n_ * 1'000; }
            }  // namespace mbstream
            """
        second = """\
            namespace mbstream {
            namespace {
            int Helper(int x) { return x; }
            }
            TEST(Other, Works) { EXPECT_EQ(Helper(1), 1); }
            }
            """
        self.assertClean(first, second)

    def test_the_stamp_is_written_only_when_clean(self):
        with tempfile.TemporaryDirectory() as directory:
            for name, text in (("a.cc", "namespace { int kA = 1; }"), ("b.cc", "namespace { int kB = 1; }")):
                with open(os.path.join(directory, name), "w", encoding="utf-8") as f:
                    f.write(text)
            batch = os.path.join(directory, "unity", "t", "batch_0.cc")
            os.makedirs(os.path.dirname(batch))
            with open(batch, "w", encoding="utf-8") as f:
                f.write('#include "a.cc"\n#include "b.cc"\n')
            stamp = os.path.join(directory, "unity", "check.stamp")
            done = subprocess.run([sys.executable, CHECK, directory, stamp, batch],
                                  capture_output=True, text=True, check=False)
            self.assertEqual(done.returncode, 0, done.stderr)
            self.assertTrue(os.path.exists(stamp))
            os.remove(stamp)
            with open(os.path.join(directory, "b.cc"), "w", encoding="utf-8") as f:
                f.write("namespace { int kA = 2; }")
            done = subprocess.run([sys.executable, CHECK, directory, stamp, batch],
                                  capture_output=True, text=True, check=False)
            self.assertEqual(done.returncode, 1)
            self.assertIn("'kA'", done.stderr)
            self.assertIn("a.cc:1", done.stderr)
            self.assertIn("b.cc:1", done.stderr)
            self.assertFalse(os.path.exists(stamp))


if __name__ == "__main__":
    unittest.main()
