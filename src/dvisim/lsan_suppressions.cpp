// SPDX-License-Identifier: Apache-2.0
// Built only with DVI_SANITIZE, into every program linking dvisim_core.
// LeakSanitizer would otherwise fail dvisim and its tests for leaks that are
// not theirs: CLN, GiNaC's number library, keeps a 26-byte allocation from
// its static initialization to the end, and GiNaC loses the half-built object
// when evaluation throws while parsing (an expression "1/0"). dvisim only
// holds GiNaC objects through GiNaC's reference-counted ex.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libcln.so\nleak:libginac.so\n";
}
// The suppression report would break dvisim's one-line error messages.
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }
