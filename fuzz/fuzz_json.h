// Shared by the libFuzzer targets of JSON files: the input written to the scratch folder and read
// with core/json.h ReadJsonFile, as every command reads its JSON files, then handed to the
// target's parser; and the callers' way with parsers that report bad data by throwing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>

#include "core/json.h"
#include "fuzz/fuzz_support.h"

namespace mesocap::fuzz {

// Writes the input to SCRATCH/`name`, reads it with ReadJsonFile and, when it parsed, calls
// `parse(json)`; all inside Run.
template <typename Parse>
void FuzzJsonFile(const char* name, const uint8_t* data, size_t size, Parse&& parse) {
  const auto path = ScratchDir() / name;
  WriteBytes(path, data, size);
  Run([&] {
    auto json = ReadJsonFile(path);
    Explain("ReadJsonFile", json.status());
    if (json.ok()) parse(*json);
  });
}

// Runs `parse()`, a parser that throws on bad data as its callers expect (they turn the exception
// into a Status), and explains what it said under `what`.
template <typename Parse>
void ExplainThrowing(const char* what, Parse&& parse) {
  try {
    parse();
    Explain(what, Status::Ok());
  } catch (const std::exception& e) {
    Explain(what, Status::Error(e.what()));
  }
}

}  // namespace mesocap::fuzz
