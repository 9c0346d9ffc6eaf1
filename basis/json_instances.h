// nlohmann::json's serializer, lexer and parser, compiled once for the whole program.
//
// Each source that writes or reads JSON text (`dump`, `json::parse`) would otherwise instantiate
// and optimize these class templates again: 25 of the build's compiler runs held their own copy of
// the serializer, 10 of the stream parser (docs/bench.md, "JSON's templates compiled once"). This
// header declares their instantiations for zbrdf's one JSON type (`nlohmann::json`) and the two
// inputs it parses (a std::istream, a std::string's characters) extern, and json_instances.cc
// defines them. The libraries' and tests' precompiled header includes it in place of
// <nlohmann/json.hpp> (cmake/ZbrdfLibrary.cmake); a source compiled without it instantiates the
// templates itself, as before, and the linker keeps one copy.
//
// Only these class templates are named. Their member function templates, and basic_json itself,
// are instantiated where they are used: an extern basic_json<> made a heavy source slower to
// compile (40 -> 41-43 s), since its small members are still inlined there.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

extern template class nlohmann::detail::serializer<nlohmann::json>;
extern template class nlohmann::detail::lexer<nlohmann::json,
                                              nlohmann::detail::input_stream_adapter>;
extern template class nlohmann::detail::lexer<
    nlohmann::json, nlohmann::detail::iterator_input_adapter<std::string::const_iterator>>;
extern template class nlohmann::detail::parser<nlohmann::json,
                                               nlohmann::detail::input_stream_adapter>;
extern template class nlohmann::detail::parser<
    nlohmann::json, nlohmann::detail::iterator_input_adapter<std::string::const_iterator>>;
