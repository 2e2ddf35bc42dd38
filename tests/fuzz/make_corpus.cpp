// SPDX-License-Identifier: GPL-3.0-or-later
// fuzz_make_corpus FOLDER: writes the fuzzer's seed corpus, made from the protocol table
// (tests/protocol/table_cases.hpp), so every address has valid messages the fuzzer starts from:
//   ADDRESS.required, ADDRESS.all       each address with its required / all arguments
//   ADDRESS.N-nan, ADDRESS.N-long       argument N as NaN (numbers) or 256 characters (texts)
//   bundle-*                            every valid message in one bundle; nested; timed; a scene edit
//   bad-*                               the malformed packets every server must refuse
// and, with a second argument, a libFuzzer dictionary: every address, argument text and type tag.
// Rerun after the table changes (tests/fuzz/make-corpus); the files are committed.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "protocol/osc_codec.hpp"
#include "tests/protocol/table_cases.hpp"

namespace {

using namespace ameoto;
using protocol::OscArgument;
using Bytes = std::vector<unsigned char>;

std::filesystem::path folder;
int written = 0;

std::string file_name(const std::string& text) {
    std::string name;
    for (char c : text) name += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.') ? c : '_';
    return name.substr(name[0] == '_' ? 1 : 0);
}

void write(const std::string& name, const Bytes& bytes) {
    std::ofstream out(folder / file_name(name), std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    ++written;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2 && argc != 3) {
        std::fprintf(stderr, "usage: fuzz_make_corpus FOLDER [DICTIONARY]\n");
        return 2;
    }
    folder = argv[1];
    std::filesystem::create_directories(folder);
    std::vector<Bytes> every_valid;
    for (const protocol::AddressSpec& spec : protocol::address_table()) {
        const Bytes required = protocol::encode_message(spec.address, test::valid_arguments(spec));
        write(std::string(spec.address) + ".required", required);
        write(std::string(spec.address) + ".all", protocol::encode_message(spec.address, test::valid_arguments(spec, true)));
        if (std::string(spec.address) != "/quit") every_valid.push_back(required);
        const auto all = test::valid_arguments(spec, true);
        for (std::size_t i = 0; i < spec.arguments.size(); ++i) {
            auto args = std::vector<OscArgument>(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(i) + 1);
            const bool text = spec.arguments[i].kind == protocol::ArgumentKind::text;
            args[i] = text ? OscArgument::from_string(std::string(256, 'a')) : test::double_argument(std::nan(""));
            write(std::string(spec.address) + "." + std::to_string(i + 1) + (text ? "-long" : "-nan"),
                  protocol::encode_message(spec.address, args));
        }
    }
    const Bytes all_in_one = protocol::encode_bundle(protocol::Timetag{}, every_valid);
    write("bundle-every-address", all_in_one);
    write("bundle-nested-2", test::nested_bundle(1, all_in_one));
    write("bundle-nested-to-the-bound", test::nested_bundle(protocol::max_bundle_depth - 1, all_in_one));
    write("bundle-timed", protocol::encode_bundle(protocol::Timetag::from_unix_seconds(1.9e9), every_valid));
    write("bundle-empty", protocol::encode_bundle(protocol::Timetag{}, {}));
    // A scene edited the way a performer does: a roof added, the listener moved, the wind turned.
    write("bundle-scene-edit",
          protocol::encode_bundle(
              protocol::Timetag{},
              {protocol::encode_message("/surface/add", {OscArgument::from_string("roof"), OscArgument::from_string("plate"),
                                                         OscArgument::from_string("tin"), OscArgument::from_float(3), OscArgument::from_float(2),
                                                         OscArgument::from_float(1), OscArgument::from_float(-1), OscArgument::from_float(2.5f)}),
               protocol::encode_message("/listener", {OscArgument::from_float(1), OscArgument::from_float(2), OscArgument::from_float(1.6f),
                                                      OscArgument::from_float(90)}),
               protocol::encode_message("/rain/wind", {OscArgument::from_float(12), OscArgument::from_float(720), OscArgument::from_float(0.5f)}),
               protocol::encode_message("/rain/dsd", {OscArgument::from_string("gamma"), OscArgument::from_float(3), OscArgument::from_float(2)}),
               protocol::encode_message("/material/liquid", {OscArgument::from_string("syrup"), OscArgument::from_float(1300),
                                                             OscArgument::from_float(0.07f), OscArgument::from_float(0.5f)}),
               protocol::encode_message("/surface/remove", {OscArgument::from_string("roof")})}));
    for (const test::BadPacket& b : test::bad_packets()) write("bad-" + b.what, b.bytes);
    if (argc == 3) {
        std::ofstream dict(argv[2]);
        dict << "# libFuzzer dictionary made by fuzz_make_corpus from the protocol table\n\"#bundle\\x00\"\n";
        for (const char* tags : {",f", ",i", ",h", ",d", ",s", ",S", ",T", ",F", ",N", ",I", ",b", ",m", ",t", ",c"})
            dict << "\"" << tags << "\"\n";
        for (const protocol::AddressSpec& spec : protocol::address_table()) {
            dict << "\"" << spec.address << "\"\n";
            for (const auto& a : spec.arguments)
                if (*a.example) dict << "\"" << a.example << "\"\n";
        }
    }
    std::printf("fuzz_make_corpus: %d inputs in %s\n", written, folder.c_str());
    return 0;
}
