// SPDX-License-Identifier: GPL-3.0-or-later
#include "protocol/take_messages.hpp"

#include <cmath>

namespace ameoto::protocol {
namespace {

OscArgument take_real(double v) {
    OscArgument a;
    a.type = 'd';
    a.number = v;
    return a;
}

OscArgument take_frame_argument(std::uint64_t frame) { return OscArgument::from_int64(static_cast<std::int64_t>(frame)); }

void add_take_material(std::vector<OscArgument>& args, const MembraneMaterial& m) {
    args.push_back(OscArgument::from_string(m.name));
    for (double v : {m.areal_density, m.tension, m.mass_damping, m.stiffness_damping, m.link_stiffness, m.total_mass, m.link_damping})
        args.push_back(take_real(v));
}

void add_take_liquid(std::vector<OscArgument>& args, const Liquid& l) {
    args.push_back(OscArgument::from_string(l.name));
    for (double v : {l.density, l.surface_tension, l.viscosity}) args.push_back(take_real(v));
}

// Reads the arguments in order against a type string ('d' any number, 'i'/'h' integers, 's' a string).
class TakeArgumentReader {
public:
    TakeArgumentReader(const DecodedMessage& m, const char* types) : m_(m) {
        const std::string want(types);
        if (m.args.size() != want.size()) {
            error_ = std::to_string(m.args.size()) + " arguments, not the " + std::to_string(want.size()) + " of take format " +
                     std::to_string(take_format_version);
            return;
        }
        for (std::size_t i = 0; i < want.size() && error_.empty(); ++i) {
            const OscArgument& a = m.args[i];
            const bool ok = want[i] == 's' ? (a.type == 's' || a.type == 'S')
                            : want[i] == 'd' ? a.is_number() && std::isfinite(a.number)
                                             : (a.type == 'i' || a.type == 'h');
            if (!ok) error_ = "argument " + std::to_string(i + 1) + " should be " + (want[i] == 's' ? "a string" : want[i] == 'd' ? "a finite number" : "an integer");
        }
    }
    const std::string& error() const { return error_; }
    double number() { return m_.args[at_++].number; }
    std::int64_t integer() { return m_.args[at_++].integer; }
    const std::string& text() { return m_.args[at_++].text; }
    MembraneMaterial material() {
        MembraneMaterial m;
        m.name = text();
        for (double* v : {&m.areal_density, &m.tension, &m.mass_damping, &m.stiffness_damping, &m.link_stiffness, &m.total_mass, &m.link_damping})
            *v = number();
        return m;
    }
    Liquid liquid() {
        Liquid l;
        l.name = text();
        for (double* v : {&l.density, &l.surface_tension, &l.viscosity}) *v = number();
        return l;
    }

private:
    const DecodedMessage& m_;
    std::size_t at_ = 0;
    std::string error_;
};

constexpr const char* take_material_types = "sddddddd";
constexpr const char* take_liquid_types = "sddd";

}  // namespace

std::vector<unsigned char> take_element(std::uint64_t frame, double rate_hz, const std::string& address,
                                        const std::vector<OscArgument>& args) {
    const double seconds = static_cast<double>(frame) / rate_hz;
    Timetag t;
    const double whole = std::floor(seconds);
    t.seconds = static_cast<std::uint32_t>(whole);
    t.fraction = static_cast<std::uint32_t>(std::fmin(4294967295.0, std::round((seconds - whole) * 4294967296.0)));
    if (t.seconds == 0 && t.fraction <= 1) t.fraction = 2;   // {0, 1} would mean "immediately"; 2^-31 s is no sample
    const std::vector<unsigned char> bundle = encode_bundle(t, {encode_message(address, args)});
    std::vector<unsigned char> out;
    out.reserve(4 + bundle.size());
    const auto size = static_cast<std::uint32_t>(bundle.size());
    for (const int shift : {24, 16, 8, 0}) out.push_back(static_cast<unsigned char>(size >> shift));
    out.insert(out.end(), bundle.begin(), bundle.end());
    return out;
}

std::vector<OscArgument> take_start_arguments(const TakeStart& s) {
    return {OscArgument::from_int(take_format_version),
            take_real(s.rate_hz),
            OscArgument::from_int(s.channels),
            OscArgument::from_int64(static_cast<std::int64_t>(s.seed)),
            OscArgument::from_int(s.node),
            OscArgument::from_int(s.limiter ? 1 : 0),
            take_real(s.full_scale_pa),
            take_real(s.level_gain_db),
            OscArgument::from_int(s.adaptive_detail ? 1 : 0),
            OscArgument::from_string(s.scene),
            OscArgument::from_string(s.format)};
}

std::vector<OscArgument> take_command_arguments(std::uint64_t frame, const Command& c) {
    return {take_frame_argument(frame), OscArgument::from_int(static_cast<int>(c.kind)), take_real(c.values[0]), take_real(c.values[1]),
            take_real(c.values[2]), take_real(c.values[3])};
}

std::vector<OscArgument> take_scene_arguments(const TakeSceneChange& change) {
    std::vector<OscArgument> args{take_frame_argument(change.frame), OscArgument::from_int(static_cast<int>(change.kind)),
                                  take_real(change.level_gain_db), OscArgument::from_string(change.scene)};
    add_take_material(args, change.material);
    add_take_liquid(args, change.liquid);
    return args;
}

std::vector<OscArgument> take_frames_arguments(std::uint64_t frames, std::uint64_t lost) {
    return {take_frame_argument(frames), OscArgument::from_int64(static_cast<std::int64_t>(lost))};
}

std::string read_take_start(const DecodedMessage& m, TakeStart& s) {
    // Format 1 is format 2 without the output format (the renderer's channels alone, as it rendered then).
    const bool first_format = !m.args.empty() && (m.args[0].type == 'i' || m.args[0].type == 'h') && m.args[0].integer == 1;
    if (!m.args.empty() && (m.args[0].type == 'i' || m.args[0].type == 'h') && m.args[0].integer != take_format_version && !first_format)
        return "take format " + std::to_string(m.args[0].integer) + ": this ameoto reads formats 1 and " + std::to_string(take_format_version);
    TakeArgumentReader r(m, first_format ? "idihiiddis" : "idihiiddiss");
    if (!r.error().empty()) return r.error();
    (void)r.integer();
    s.rate_hz = r.number();
    s.channels = static_cast<int>(r.integer());
    s.seed = static_cast<std::uint64_t>(r.integer());
    s.node = static_cast<int>(r.integer());
    s.limiter = r.integer() != 0;
    s.full_scale_pa = r.number();
    s.level_gain_db = r.number();
    s.adaptive_detail = r.integer() != 0;
    s.scene = r.text();
    s.format = first_format ? std::string() : r.text();
    if (!first_format && s.format.empty()) return "the output format is empty (\"stereo\", \"ambix:1\", \"binaural\", ...)";
    if (!(s.rate_hz >= 8000.0 && s.rate_hz <= 192000.0)) return "rate " + std::to_string(s.rate_hz) + " Hz is not 8000..192000";
    if (s.channels < 1 || s.channels > 16) return "channels " + std::to_string(s.channels) + " is not 1..16";
    if (s.node < 0 || s.node > 16) return "node " + std::to_string(s.node) + " is not 0..16";
    if (!(s.full_scale_pa > 0.0)) return "full scale must be > 0 Pa";
    return "";
}

std::string read_take_command(const DecodedMessage& m, std::uint64_t& frame, Command& c) {
    TakeArgumentReader r(m, "hidddd");
    if (!r.error().empty()) return r.error();
    const std::int64_t f = r.integer();
    const std::int64_t kind = r.integer();
    if (f < 0) return "a negative frame";
    using K = CommandKind;
    const bool plain = kind == static_cast<int>(K::drop) || kind == static_cast<int>(K::rain_rate) || kind == static_cast<int>(K::lod) ||
                       kind == static_cast<int>(K::wind) || kind == static_cast<int>(K::listener) || kind == static_cast<int>(K::gain) ||
                       kind == static_cast<int>(K::level) || kind == static_cast<int>(K::orientation);
    if (!plain) return "command kind " + std::to_string(kind) + " is not one a take records as a command";
    frame = static_cast<std::uint64_t>(f);
    c = Command{};
    c.kind = static_cast<K>(kind);
    for (double& v : c.values) v = r.number();
    return "";
}

std::string read_take_scene(const DecodedMessage& m, TakeSceneChange& change) {
    TakeArgumentReader r(m, (std::string("hids") + take_material_types + take_liquid_types).c_str());
    if (!r.error().empty()) return r.error();
    const std::int64_t f = r.integer();
    const std::int64_t kind = r.integer();
    if (f < 0) return "a negative frame";
    using K = CommandKind;
    if (kind != static_cast<int>(K::load_scene) && kind != static_cast<int>(K::swap_surface) && kind != static_cast<int>(K::swap_liquid))
        return "scene change kind " + std::to_string(kind) + " is not a load, a surface or a liquid";
    change.frame = static_cast<std::uint64_t>(f);
    change.kind = static_cast<K>(kind);
    change.level_gain_db = r.number();
    change.scene = r.text();
    change.material = r.material();
    change.liquid = r.liquid();
    // The material and liquid are what ameotod built with (presets included, which OSC's ranges need not
    // admit); building the scene again checks them (a refusal names the reason).
    return "";
}

std::string read_take_frames(const DecodedMessage& m, std::uint64_t& frames, std::uint64_t& lost) {
    TakeArgumentReader r(m, "hh");
    if (!r.error().empty()) return r.error();
    const std::int64_t f = r.integer(), l = r.integer();
    if (f < 0 || l < 0) return "a negative count";
    frames = static_cast<std::uint64_t>(f);
    lost = static_cast<std::uint64_t>(l);
    return "";
}

}  // namespace ameoto::protocol
