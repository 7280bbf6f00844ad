// CRS and linear units from GeoTIFF keys or OGC WKT (see crs.hpp): the two parsers, the
// built-in EPSG unit table, and the choice between the records a file carries.
#include "las/crs.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>

#include "io/byte_reader.hpp"
#include "io/file.hpp"

namespace lidarscout::las {
namespace {

// ---- Built-in EPSG unit table ---------------------------------------------------------
// Generated from the EPSG registry v10.076 (PROJ's proj.db, 2022-08-31): every projected CRS
// whose axes are in US survey feet (UoM 9003) or international feet (UoM 9002), deprecated
// codes included since old files still carry them.
constexpr int kUsFootProjected[] = {
    2155, 2194, 2204, 2225, 2226, 2227, 2228, 2229, 2230, 2231, 2232, 2233, 2234, 2235, 2236, 2237,
    2238, 2239, 2240, 2241, 2242, 2243, 2244, 2245, 2246, 2247, 2248, 2249, 2250, 2254, 2255, 2257,
    2258, 2259, 2260, 2261, 2262, 2263, 2264, 2267, 2268, 2271, 2272, 2274, 2275, 2276, 2277, 2278,
    2279, 2283, 2284, 2285, 2286, 2287, 2288, 2289, 2870, 2871, 2872, 2873, 2874, 2875, 2876, 2877,
    2878, 2879, 2880, 2881, 2882, 2883, 2884, 2885, 2886, 2887, 2888, 2889, 2890, 2891, 2892, 2893,
    2894, 2895, 2899, 2900, 2902, 2903, 2904, 2905, 2906, 2907, 2908, 2911, 2912, 2915, 2916, 2917,
    2918, 2919, 2920, 2924, 2925, 2926, 2927, 2928, 2929, 2930, 2964, 2965, 2966, 2967, 2968, 3089,
    3091, 3102, 3363, 3365, 3404, 3417, 3418, 3419, 3420, 3421, 3422, 3423, 3424, 3425, 3426, 3427,
    3428, 3429, 3430, 3431, 3432, 3433, 3434, 3435, 3436, 3437, 3438, 3441, 3442, 3443, 3444, 3445,
    3446, 3451, 3452, 3453, 3454, 3455, 3456, 3457, 3458, 3459, 3485, 3487, 3490, 3492, 3494, 3496,
    3498, 3500, 3502, 3504, 3506, 3508, 3510, 3512, 3515, 3517, 3519, 3521, 3523, 3525, 3527, 3529,
    3531, 3533, 3535, 3537, 3539, 3541, 3543, 3545, 3547, 3549, 3551, 3553, 3560, 3561, 3562, 3563,
    3564, 3565, 3566, 3567, 3568, 3569, 3570, 3582, 3584, 3586, 3598, 3600, 3608, 3610, 3612, 3614,
    3616, 3618, 3620, 3622, 3624, 3626, 3628, 3630, 3632, 3640, 3642, 3650, 3652, 3654, 3658, 3660,
    3662, 3664, 3668, 3670, 3672, 3674, 3677, 3680, 3683, 3686, 3688, 3690, 3692, 3696, 3698, 3700,
    3728, 3729, 3730, 3731, 3732, 3733, 3734, 3735, 3736, 3737, 3738, 3739, 3753, 3754, 3755, 3756,
    3757, 3758, 3759, 3760, 3991, 3992, 4217, 4399, 4400, 4401, 4402, 4403, 4404, 4405, 4406, 4407,
    4408, 4409, 4410, 4411, 4412, 4413, 4418, 4419, 4420, 4421, 4422, 4423, 4424, 4425, 4426, 4427,
    4428, 4429, 4430, 4431, 4432, 4433, 4438, 4439, 4455, 4456, 4457, 5623, 5624, 5625, 5646, 5654,
    5655, 6200, 6201, 6202, 6411, 6413, 6416, 6418, 6420, 6422, 6424, 6426, 6428, 6430, 6432, 6434,
    6436, 6438, 6441, 6443, 6445, 6447, 6449, 6451, 6453, 6455, 6457, 6459, 6461, 6463, 6465, 6467,
    6469, 6471, 6473, 6475, 6477, 6479, 6484, 6486, 6488, 6490, 6492, 6501, 6503, 6505, 6507, 6510,
    6517, 6519, 6521, 6523, 6525, 6527, 6529, 6531, 6533, 6535, 6537, 6539, 6541, 6543, 6549, 6551,
    6553, 6555, 6563, 6565, 6568, 6572, 6574, 6576, 6578, 6582, 6584, 6586, 6588, 6590, 6593, 6595,
    6597, 6599, 6601, 6603, 6605, 6607, 6609, 6612, 6614, 6616, 6618, 6625, 6626, 6627, 6633, 6880,
    6923, 6925, 6966, 6997, 7057, 7058, 7059, 7060, 7061, 7062, 7063, 7064, 7065, 7066, 7067, 7068,
    7069, 7070, 7128, 7132, 7258, 7260, 7262, 7264, 7266, 7268, 7270, 7272, 7274, 7276, 7278, 7280,
    7282, 7284, 7286, 7288, 7290, 7292, 7294, 7296, 7298, 7300, 7302, 7304, 7306, 7308, 7310, 7312,
    7314, 7316, 7318, 7320, 7322, 7324, 7326, 7328, 7330, 7332, 7334, 7336, 7338, 7340, 7342, 7344,
    7346, 7348, 7350, 7352, 7354, 7356, 7358, 7360, 7362, 7364, 7366, 7368, 7370, 7587, 7588, 7589,
    7590, 7591, 7592, 7593, 7594, 7595, 7596, 7597, 7598, 7599, 7600, 7601, 7602, 7603, 7604, 7605,
    7606, 7607, 7608, 7609, 7610, 7611, 7612, 7613, 7614, 7615, 7616, 7617, 7618, 7619, 7620, 7621,
    7622, 7623, 7624, 7625, 7626, 7627, 7628, 7629, 7630, 7631, 7632, 7633, 7634, 7635, 7636, 7637,
    7638, 7639, 7640, 7641, 7642, 7643, 7644, 7645, 8035, 8036, 8091, 8093, 8096, 8098, 8100, 8102,
    8104, 8106, 8108, 8110, 8112, 8114, 8116, 8118, 8120, 8122, 8124, 8126, 8128, 8130, 8132, 8134,
    8136, 8138, 8140, 8142, 8144, 8146, 8148, 8150, 8152, 8154, 8156, 8158, 8160, 8162, 8164, 8166,
    8168, 8170, 8172, 8177, 8180, 8182, 8185, 8189, 8193, 8197, 8200, 8202, 8204, 8206, 8208, 8210,
    8213, 8216, 8220, 8224, 8226, 8380, 8382, 8384, 8387, 8518, 8519, 8520, 8521, 8522, 8523, 8524,
    8525, 8526, 8527, 8528, 8529, 8531, 8533, 8534, 8535, 8536, 8538, 8539, 8540, 9748, 9749, 26729,
    26730, 26731, 26732, 26733, 26734, 26735, 26736, 26737, 26738, 26739, 26740, 26741, 26742,
    26743, 26744, 26745, 26746, 26747, 26748, 26749, 26750, 26751, 26752, 26753, 26754, 26755,
    26756, 26757, 26758, 26759, 26760, 26766, 26767, 26768, 26769, 26770, 26771, 26772, 26773,
    26774, 26775, 26776, 26777, 26778, 26779, 26780, 26781, 26782, 26783, 26784, 26785, 26786,
    26787, 26791, 26792, 26793, 26794, 26795, 26796, 26797, 26798, 26799, 26801, 26802, 26803,
    26811, 26812, 26813, 26847, 26848, 26849, 26850, 26851, 26852, 26853, 26854, 26855, 26856,
    26857, 26858, 26859, 26860, 26861, 26862, 26863, 26864, 26865, 26866, 26867, 26868, 26869,
    26870, 32001, 32002, 32003, 32005, 32006, 32007, 32008, 32009, 32010, 32011, 32012, 32013,
    32014, 32015, 32016, 32017, 32018, 32019, 32020, 32021, 32022, 32023, 32024, 32025, 32026,
    32027, 32028, 32029, 32030, 32031, 32033, 32034, 32035, 32036, 32037, 32038, 32039, 32040,
    32041, 32042, 32043, 32044, 32045, 32046, 32047, 32048, 32049, 32050, 32051, 32052, 32053,
    32054, 32055, 32056, 32057, 32058, 32064, 32065, 32066, 32067, 32074, 32075, 32076, 32077,
    32099, 32164, 32165, 32166, 32167, 32664, 32665, 32666, 32667,
};
constexpr int kFootProjected[] = {
    2222, 2223, 2224, 2251, 2252, 2253, 2256, 2265, 2266, 2269, 2270, 2273, 2280, 2281, 2282, 2867,
    2868, 2869, 2896, 2897, 2898, 2901, 2909, 2910, 2913, 2914, 2921, 2922, 2923, 2992, 2994, 3080,
    3359, 3361, 3479, 3481, 3483, 3588, 3590, 3593, 3605, 3634, 3636, 3644, 3646, 3648, 3656, 3676,
    3679, 3682, 5588, 6128, 6129, 6141, 6391, 6405, 6407, 6409, 6494, 6496, 6499, 6515, 6545, 6547,
    6557, 6559, 6561, 6570, 6785, 6787, 6789, 6791, 6793, 6795, 6797, 6799, 6801, 6803, 6805, 6807,
    6809, 6811, 6813, 6815, 6817, 6819, 6821, 6823, 6825, 6827, 6829, 6831, 6833, 6835, 6837, 6839,
    6841, 6843, 6845, 6847, 6849, 6851, 6853, 6855, 6857, 6859, 6861, 6863, 6868, 6885, 6887, 7119,
    7120, 7121, 7122, 7123, 7124, 7125, 7126, 7127, 8065, 8066, 8067, 8068, 8312, 8314, 8316, 8318,
    8320, 8322, 8324, 8326, 8328, 8330, 8332, 8334, 8336, 8338, 8340, 8342, 8344, 8346, 8348, 20050,
};

// Metre families, as ranges in which every code exists in the same registry and is in metres.
struct CodeRange {
    int first, last;
};
constexpr CodeRange kMetreProjected[] = {
    {2056, 2056},                                                                   // CH1903+ / LV95
    {2154, 2154},                                                                   // RGF93 v1 / Lambert-93
    {2180, 2180},                                                                   // ETRF2000-PL / CS92
    {2193, 2193},                                                                   // NZGD2000 / NZTM 2000
    {2944, 2962},                                                                   // NAD83(CSRS) / MTM, UTM 11N-21N
    {3005, 3006},                                                                   // NAD83 / BC Albers; SWEREF99 TM
    {3035, 3035},                                                                   // ETRS89-extended / LAEA Europe
    {3763, 3763},                                                                   // ETRS89 / Portugal TM06
    {3857, 3857},                                                                   // WGS 84 / Pseudo-Mercator
    {3942, 3950},                                                                   // RGF93 v1 / CC42-CC50
    {5070, 5070},                                                                   // NAD83 / Conus Albers
    {5514, 5514},                                                                   // S-JTSK / Krovak East North
    {6339, 6348},                                                                   // NAD83(2011) / UTM 10N-19N
    {6350, 6350},                                                                   // NAD83(2011) / Conus Albers
    {7846, 7859},                                                                   // GDA2020 / MGA 46-59
    {25828, 25838},                                                                 // ETRS89 / UTM 28N-38N
    {26901, 26923},                                                                 // NAD83 / UTM 1N-23N
    {26929, 26946}, {26948, 26998},                                                 // NAD83 state plane (m)
    {27700, 27700},                                                                 // OSGB36 / British National Grid
    {28348, 28358},                                                                 // GDA94 / MGA 48-58
    {28992, 28992},                                                                 // Amersfoort / RD New
    {31466, 31469},                                                                 // DHDN / 3-degree GK 2-5
    {32100, 32100}, {32104, 32104}, {32107, 32130}, {32133, 32159}, {32161, 32161},  // NAD83 state plane (m)
    {32201, 32260}, {32301, 32360},                                                 // WGS 72 / UTM
    {32601, 32660}, {32701, 32760},                                                 // WGS 84 / UTM
};

// Vertical CRSs: all those in feet, and common ones in metres (same registry).
constexpr int kUsFootVertical[] = {5702, 6358, 6359, 6360, 8052, 8053};
constexpr int kFootVertical[] = {5614, 6130, 6131, 6132, 8050, 8051, 8228, 8897};
constexpr int kMetreVertical[] = {3855, 5701, 5703, 5705, 5709, 5710, 5711, 5713,
                                  5714, 5720, 5773, 5776, 5782, 5941, 6357, 7837};

template <std::size_t N>
constexpr bool sorted(const int (&codes)[N]) {
    return std::is_sorted(std::begin(codes), std::end(codes));
}
static_assert(sorted(kUsFootProjected) && sorted(kFootProjected) && sorted(kUsFootVertical) &&
              sorted(kFootVertical) && sorted(kMetreVertical));

template <std::size_t N>
bool listed(const int (&codes)[N], int code) {
    return std::binary_search(std::begin(codes), std::end(codes), code);
}

// ---- Units ------------------------------------------------------------------------------
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Unit {
    LinearUnit kind = LinearUnit::Unknown;
    double to_metres = kNaN;
    std::string name;
};

const char* canonical_name(LinearUnit kind) {
    switch (kind) {
        case LinearUnit::Metre: return "metre";
        case LinearUnit::InternationalFoot: return "foot";
        case LinearUnit::UsSurveyFoot: return "US survey foot";
        default: return "";
    }
}

Unit unit_of_kind(LinearUnit kind) { return {kind, unit_to_metres(kind), canonical_name(kind)}; }

bool close_to(double value, double target) { return std::abs(value - target) <= 1e-8 * target; }

// A unit given by its size in metres (WKT UNIT factor, GeoTIFF ProjLinearUnitSizeGeoKey).
Unit unit_of_factor(double metres, std::string name) {
    Unit u{LinearUnit::Unknown, kNaN, std::move(name)};
    if (!std::isfinite(metres) || metres <= 0) return u;
    u.to_metres = metres;
    if (close_to(metres, 1.0)) u.kind = LinearUnit::Metre;
    else if (close_to(metres, kFootMetres)) u.kind = LinearUnit::InternationalFoot;
    else if (close_to(metres, kUsSurveyFootMetres)) u.kind = LinearUnit::UsSurveyFoot;
    else u.kind = LinearUnit::Other;
    if (u.kind != LinearUnit::Other) u.to_metres = unit_to_metres(u.kind);  // exact value
    return u;
}

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::string upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

// What a unit's name suggests, to catch names that contradict their factor.
LinearUnit unit_suggested_by_name(std::string_view name) {
    const std::string n = lower(name);
    auto has = [&](const char* s) { return n.find(s) != std::string::npos; };
    if (has("us survey") || has("us_survey") || has("foot_us") || has("ftus") || has("us foot") || has("us_foot")) {
        return LinearUnit::UsSurveyFoot;
    }
    if (has("foot") || has("feet")) return LinearUnit::InternationalFoot;
    if (has("metre") || has("meter")) return LinearUnit::Metre;
    return LinearUnit::Unknown;
}

// EPSG units of measure used by GeoTIFF ProjLinearUnitsGeoKey / VerticalUnitsGeoKey.
std::optional<LinearUnit> unit_of_uom_code(int code) {
    switch (code) {
        case 9001: return LinearUnit::Metre;
        case 9002: return LinearUnit::InternationalFoot;
        case 9003: return LinearUnit::UsSurveyFoot;
        default: return std::nullopt;
    }
}

// The unit the record gives, checked against the EPSG table; or, when the record gives none,
// the table's unit for the CRS code. `what` names the CRS kind in warnings.
Unit resolve_unit(std::optional<Unit> given, std::optional<int> epsg, LinearUnit (*table)(int), const char* what,
                  Diagnostics& warnings) {
    const LinearUnit listed_unit = epsg ? table(*epsg) : LinearUnit::Unknown;
    if (given) {
        if (listed_unit != LinearUnit::Unknown && given->kind != LinearUnit::Unknown && given->kind != listed_unit) {
            warnings.warn(std::string("the ") + what + " unit is given as " + unit_name(given->kind) + " but EPSG:" +
                               std::to_string(*epsg) + " is in " + unit_name(listed_unit) + "; reporting " +
                               unit_name(given->kind) + " as the file says");
        }
        return *given;
    }
    if (listed_unit != LinearUnit::Unknown) return unit_of_kind(listed_unit);
    if (epsg) {
        warnings.warn(std::string("no ") + what + " unit is given and EPSG:" + std::to_string(*epsg) +
                           " is not in the built-in unit table; the unit is unknown");
    }
    return {};
}

void set_horizontal(Crs& c, const Unit& u) {
    c.horizontal_unit = u.kind;
    c.horizontal_to_metres = u.to_metres;
    c.horizontal_unit_name = u.name;
}

void set_vertical(Crs& c, const Unit& u) {
    c.vertical_unit = u.kind;
    c.vertical_to_metres = u.to_metres;
    c.vertical_unit_name = u.name;
}

// ---- GeoTIFF keys -------------------------------------------------------------------------
enum GeoKey : int {
    kModelType = 1024,
    kCitation = 1026,
    kGeographicType = 2048,
    kGeogCitation = 2049,
    kGeogLinearUnits = 2052,
    kProjectedType = 3072,
    kPcsCitation = 3073,
    kProjLinearUnits = 3076,
    kProjLinearUnitSize = 3077,
    kVerticalType = 4096,
    kVerticalUnits = 4099,
};
constexpr int kTagKeyDirectory = 34735, kTagDoubleParams = 34736, kTagAsciiParams = 34737;
constexpr int kUserDefined = 32767;
constexpr int kModelProjected = 1, kModelGeographic = 2, kModelGeocentric = 3;

struct GeoKeys {
    std::map<int, int> shorts;
    std::map<int, double> doubles;
    std::map<int, std::string> strings;

    std::optional<int> short_value(int key) const {
        auto it = shorts.find(key);
        return it == shorts.end() ? std::nullopt : std::optional<int>(it->second);
    }
    std::optional<double> double_value(int key) const {
        auto it = doubles.find(key);
        return it == doubles.end() ? std::nullopt : std::optional<double>(it->second);
    }
};

// A GeoAsciiParams entry without its '|' terminator, NULs and surrounding blanks.
std::string citation(std::span<const std::uint8_t> bytes) {
    std::string s(bytes.begin(), bytes.end());
    while (!s.empty() && (s.back() == '|' || s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back())))) {
        s.pop_back();
    }
    return s;
}

// Decodes the key directory; keys that point outside their arrays are dropped with a warning.
GeoKeys decode_geokeys(std::span<const std::uint8_t> dir, std::span<const std::uint8_t> doubles,
                       std::span<const std::uint8_t> ascii, Diagnostics& warnings) {
    GeoKeys keys;
    if (dir.size() < 8) {
        warnings.warn("GeoKeyDirectory is " + std::to_string(dir.size()) + " bytes, shorter than its 8-byte header");
        return keys;
    }
    const std::size_t n_shorts = dir.size() / 2;
    auto word = [&](std::size_t i) { return static_cast<int>(io::load_le<std::uint16_t>(dir.data() + 2 * i)); };
    if (word(0) != 1) warnings.warn("GeoKeyDirectory version " + std::to_string(word(0)) + " (expected 1)");
    std::size_t count = static_cast<std::size_t>(word(3));
    const std::size_t fits = (n_shorts - 4) / 4;
    if (count > fits) {
        warnings.warn("GeoKeyDirectory announces " + std::to_string(count) + " keys but its " +
                           std::to_string(dir.size()) + " bytes hold only " + std::to_string(fits));
        count = fits;
    }
    const std::size_t n_doubles = doubles.size() / 8;
    std::size_t zero_ids = 0;
    for (std::size_t i = 0; i < count; ++i) {
        const int id = word(4 + 4 * i), location = word(5 + 4 * i);
        const std::size_t n = static_cast<std::size_t>(word(6 + 4 * i)),
                          value = static_cast<std::size_t>(word(7 + 4 * i));
        const std::string key = "GeoKey " + std::to_string(id);
        if (id == 0) {
            ++zero_ids;
        } else if (location == 0) {
            keys.shorts[id] = static_cast<int>(value);
        } else if (location == kTagKeyDirectory) {
            if (value < n_shorts) keys.shorts[id] = word(value);
            else warnings.warn(key + " points past the end of the key directory; ignored");
        } else if (location == kTagDoubleParams) {
            if (n == 0 || value + n > n_doubles) {
                warnings.warn(key + " refers to doubles " + std::to_string(value) + ".." + std::to_string(value + n) +
                                   " but GeoDoubleParams holds " + std::to_string(n_doubles) + "; ignored");
            } else {
                keys.doubles[id] = io::load_le<double>(doubles.data() + 8 * value);
            }
        } else if (location == kTagAsciiParams) {
            if (value + n > ascii.size()) {
                warnings.warn(key + " refers to characters " + std::to_string(value) + ".." +
                                   std::to_string(value + n) + " but GeoAsciiParams holds " +
                                   std::to_string(ascii.size()) + "; ignored");
            } else {
                keys.strings[id] = citation(ascii.subspan(value, n));
            }
        } else {
            warnings.warn(key + " has an unknown location tag " + std::to_string(location) + "; ignored");
        }
    }
    if (zero_ids > 0) warnings.warn(std::to_string(zero_ids) + " GeoKey entries with id 0 ignored");
    return keys;
}

// An EPSG code from a *TypeGeoKey: 0 (undefined) and 32767 (user-defined) are no code;
// values above 32767 are not EPSG codes (private range or garbage) and are reported.
std::optional<int> epsg_from_key(const GeoKeys& keys, int key, const char* key_name, Diagnostics& warnings) {
    const auto v = keys.short_value(key);
    if (!v || *v == 0 || *v == kUserDefined) return std::nullopt;
    if (*v > kUserDefined) {
        warnings.warn(std::string(key_name) + " " + std::to_string(*v) + " is not an EPSG code; ignored");
        return std::nullopt;
    }
    return *v;
}

// The unit a units key gives (with the size key for user-defined units), if it gives one.
std::optional<Unit> unit_from_key(const GeoKeys& keys, int unit_key, int size_key, const char* key_name,
                                  Diagnostics& warnings) {
    const auto code = keys.short_value(unit_key);
    const auto size = size_key ? keys.double_value(size_key) : std::nullopt;
    if (code && *code != kUserDefined) {
        if (auto kind = unit_of_uom_code(*code)) return unit_of_kind(*kind);
        warnings.warn(std::string(key_name) + " " + std::to_string(*code) + " is not a known linear unit code");
        return Unit{};
    }
    if (size) return unit_of_factor(*size, "user-defined");
    if (code) warnings.warn(std::string(key_name) + " says user-defined but no unit size is given");
    return code ? std::optional<Unit>(Unit{}) : std::nullopt;
}

Crs crs_from_geokeys(const GeoKeys& keys, Diagnostics& warnings) {
    Crs c;
    c.source = "geotiff";
    const int model = keys.short_value(kModelType).value_or(0);
    const bool has_projected = keys.shorts.count(kProjectedType) > 0;
    for (int k : {kPcsCitation, kCitation, kGeogCitation}) {
        if (auto it = keys.strings.find(k); it != keys.strings.end() && !it->second.empty()) {
            c.name = it->second;
            break;
        }
    }
    if (model == kModelGeographic || (model == 0 && !has_projected && keys.shorts.count(kGeographicType))) {
        c.geographic = true;
        c.epsg = epsg_from_key(keys, kGeographicType, "GeographicTypeGeoKey", warnings);
        c.horizontal_unit_name = "degree";
    } else if (model == kModelGeocentric) {
        c.epsg = epsg_from_key(keys, kGeographicType, "GeographicTypeGeoKey", warnings);
        set_horizontal(c, unit_from_key(keys, kGeogLinearUnits, 0, "GeogLinearUnitsGeoKey", warnings).value_or(Unit{}));
    } else if (model == kModelProjected || has_projected || (model == 0 && keys.shorts.count(kProjLinearUnits))) {
        c.epsg = epsg_from_key(keys, kProjectedType, "ProjectedCSTypeGeoKey", warnings);
        auto given = unit_from_key(keys, kProjLinearUnits, kProjLinearUnitSize, "ProjLinearUnitsGeoKey", warnings);
        set_horizontal(c, resolve_unit(given, c.epsg, projected_unit_of_epsg, "horizontal", warnings));
    }
    c.vertical_epsg = epsg_from_key(keys, kVerticalType, "VerticalCSTypeGeoKey", warnings);
    auto vertical = unit_from_key(keys, kVerticalUnits, 0, "VerticalUnitsGeoKey", warnings);
    set_vertical(c, resolve_unit(vertical, c.vertical_epsg, vertical_unit_of_epsg, "vertical", warnings));
    return c;
}

// ---- OGC WKT ------------------------------------------------------------------------------
// A WKT element: KEYWORD[atom or element, ...]; atoms are quoted strings or bare values.
struct WktNode {
    std::string keyword;  // upper case
    std::vector<std::string> atoms;
    std::vector<WktNode> children;
};

struct WktSyntaxError {
    std::string what;
    std::size_t position;
};

// Recursive-descent reader for WKT1 and WKT2 (either bracket style), with a nesting cap.
class WktReader {
public:
    explicit WktReader(std::string_view text) : s_(text) {}

    // The root element; `trailing` is set when text other than blanks follows it.
    WktNode read(bool& trailing) {
        skip_blanks();
        std::string keyword = bare_token();
        if (keyword.empty()) fail("expected a keyword");
        WktNode root = element(std::move(keyword), 0);
        skip_blanks();
        trailing = pos_ < s_.size();
        return root;
    }

private:
    static constexpr int kMaxDepth = 64;

    [[noreturn]] void fail(std::string what) const { throw WktSyntaxError{std::move(what), pos_}; }
    char peek() const { return pos_ < s_.size() ? s_[pos_] : '\0'; }
    void skip_blanks() {
        while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
    }
    static bool is_delimiter(char c) {
        return c == ',' || c == '[' || c == ']' || c == '(' || c == ')' || c == '"' || c == '\0' ||
               std::isspace(static_cast<unsigned char>(c));
    }
    std::string bare_token() {
        const std::size_t begin = pos_;
        while (pos_ < s_.size() && !is_delimiter(s_[pos_])) ++pos_;
        return std::string(s_.substr(begin, pos_ - begin));
    }
    std::string quoted() {
        std::string out;
        ++pos_;  // opening quote
        for (;;) {
            if (pos_ >= s_.size()) fail("unterminated string");
            const char c = s_[pos_++];
            if (c != '"') {
                out += c;
            } else if (peek() == '"') {  // "" is an escaped quote
                out += '"';
                ++pos_;
            } else {
                return out;
            }
        }
    }
    WktNode element(std::string keyword, int depth) {
        if (depth >= kMaxDepth) fail("nesting deeper than " + std::to_string(kMaxDepth));
        WktNode node;
        node.keyword = upper(keyword);
        skip_blanks();
        if (peek() != '[' && peek() != '(') fail("expected '[' after " + keyword);
        ++pos_;
        skip_blanks();
        if (peek() == ']' || peek() == ')') {
            ++pos_;
            return node;
        }
        for (;;) {
            skip_blanks();
            if (peek() == '"') {
                node.atoms.push_back(quoted());
            } else {
                std::string token = bare_token();
                if (token.empty()) fail("expected a value in " + keyword);
                skip_blanks();
                if (peek() == '[' || peek() == '(') node.children.push_back(element(std::move(token), depth + 1));
                else node.atoms.push_back(std::move(token));
            }
            skip_blanks();
            const char c = peek();
            ++pos_;
            if (c == ']' || c == ')') return node;
            if (c != ',') fail("expected ',' or ']' in " + keyword);
        }
    }

    std::string_view s_;
    std::size_t pos_ = 0;
};

bool keyword_in(const WktNode& n, std::initializer_list<std::string_view> keywords) {
    return std::find(keywords.begin(), keywords.end(), n.keyword) != keywords.end();
}

bool is_horizontal(const WktNode& n) {
    return keyword_in(n, {"PROJCS", "PROJCRS", "PROJECTEDCRS", "GEOGCS", "GEOGCRS", "GEOGRAPHICCRS", "GEOCCS",
                          "GEODCRS", "GEODETICCRS", "LOCAL_CS", "ENGCRS", "ENGINEERINGCRS"});
}
bool is_vertical(const WktNode& n) { return keyword_in(n, {"VERT_CS", "VERTCS", "VERTCRS", "VERTICALCRS"}); }
bool is_compound(const WktNode& n) { return keyword_in(n, {"COMPD_CS", "COMPOUNDCRS"}); }

const WktNode* first_child(const WktNode& n, bool (*pred)(const WktNode&)) {
    for (const auto& c : n.children) {
        if (pred(c)) return &c;
    }
    return nullptr;
}

const WktNode* child_named(const WktNode& n, std::initializer_list<std::string_view> keywords) {
    for (const auto& c : n.children) {
        if (keyword_in(c, keywords)) return &c;
    }
    return nullptr;
}

bool is_geographic(const WktNode& n) {
    if (keyword_in(n, {"GEOGCS", "GEOGCRS", "GEOGRAPHICCRS"})) return true;
    // A WKT2 geodetic CRS is geographic when its coordinate system is ellipsoidal.
    const WktNode* cs = child_named(n, {"CS"});
    return keyword_in(n, {"GEODCRS", "GEODETICCRS"}) && cs && !cs->atoms.empty() &&
           lower(cs->atoms[0]) == "ellipsoidal";
}

// The EPSG code of a CRS element: its last direct AUTHORITY["EPSG",...] or ID["EPSG",...].
std::optional<int> wkt_epsg(const WktNode& crs, Diagnostics& warnings) {
    std::optional<int> code;
    for (const auto& c : crs.children) {
        if (!keyword_in(c, {"AUTHORITY", "ID"}) || c.atoms.size() < 2 || lower(c.atoms[0]) != "epsg") continue;
        int v = 0;
        const std::string& text = c.atoms[1];
        auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (ec != std::errc() || end != text.data() + text.size() || v <= 0) {
            warnings.warn("EPSG code '" + text + "' of " + crs.keyword + " is not a positive integer; ignored");
            continue;
        }
        code = v;
    }
    return code;
}

// The length unit of a CRS element: a direct UNIT/LENGTHUNIT child, else the first axis's.
std::optional<Unit> wkt_unit(const WktNode& crs, Diagnostics& warnings) {
    const WktNode* unit = child_named(crs, {"UNIT", "LENGTHUNIT"});
    for (const auto& c : crs.children) {
        if (unit) break;
        if (c.keyword == "AXIS") unit = child_named(c, {"UNIT", "LENGTHUNIT"});
    }
    if (!unit) return std::nullopt;
    const std::string name = unit->atoms.empty() ? std::string() : unit->atoms[0];
    double factor = kNaN;
    if (unit->atoms.size() >= 2) {
        const std::string& text = unit->atoms[1];
        auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), factor);
        if (ec != std::errc() || end != text.data() + text.size()) factor = kNaN;
    }
    Unit u = unit_of_factor(factor, name);
    if (u.kind == LinearUnit::Unknown) {
        warnings.warn("unit '" + name + "' of " + crs.keyword + " has no valid conversion factor");
        return u;
    }
    const LinearUnit suggested = unit_suggested_by_name(name);
    if (suggested != LinearUnit::Unknown && suggested != u.kind) {
        warnings.warn("unit '" + name + "' of " + crs.keyword + " has factor " + unit->atoms[1] + ", which is " +
                           unit_name(u.kind) + "; using the factor");
    }
    return u;
}

struct WktParts {
    const WktNode* horizontal = nullptr;
    const WktNode* vertical = nullptr;
};

WktParts split_wkt(const WktNode& root, Diagnostics& warnings) {
    const WktNode* crs = &root;
    if (root.keyword == "BOUNDCRS") {  // WKT2 CRS with a transformation: describe the source CRS
        const WktNode* source = child_named(root, {"SOURCECRS"});
        crs = source && !source->children.empty() ? &source->children.front() : nullptr;
        if (!crs) return {};
    }
    if (is_compound(*crs)) return {first_child(*crs, is_horizontal), first_child(*crs, is_vertical)};
    if (is_vertical(*crs)) return {nullptr, crs};
    if (is_horizontal(*crs)) {
        const WktNode* nested = first_child(*crs, is_vertical);
        if (nested) warnings.warn("vertical CRS nested inside " + crs->keyword + " (not standard WKT); read anyway");
        return {crs, nested};
    }
    warnings.warn("WKT root " + crs->keyword + " is not a coordinate reference system");
    return {};
}

Crs crs_from_wkt(const WktNode& root, Diagnostics& warnings) {
    Crs c;
    c.source = "wkt";
    c.name = root.atoms.empty() ? std::string() : root.atoms[0];
    const WktParts parts = split_wkt(root, warnings);
    if (!parts.horizontal && !parts.vertical) {
        c.source = "none";
        return c;
    }
    if (const WktNode* h = parts.horizontal) {
        c.epsg = wkt_epsg(*h, warnings);
        if (is_geographic(*h)) {
            c.geographic = true;
            const WktNode* unit = child_named(*h, {"UNIT", "ANGLEUNIT"});
            c.horizontal_unit_name = unit && !unit->atoms.empty() ? unit->atoms[0] : "degree";
        } else {
            set_horizontal(
                c, resolve_unit(wkt_unit(*h, warnings), c.epsg, projected_unit_of_epsg, "horizontal", warnings));
        }
    }
    if (const WktNode* v = parts.vertical) {
        c.vertical_epsg = wkt_epsg(*v, warnings);
        set_vertical(
            c, resolve_unit(wkt_unit(*v, warnings), c.vertical_epsg, vertical_unit_of_epsg, "vertical", warnings));
    }
    return c;
}

// ---- Choosing between the records of a file ------------------------------------------------
constexpr std::uint64_t kMaxCrsRecordBytes = 1u << 20;  // larger CRS records are not CRS records

const Vlr* find_projection_record(const std::vector<Vlr>& vlrs, const std::vector<Vlr>& evlrs, std::uint16_t id) {
    const Vlr* v = find_vlr(vlrs, "LASF_Projection", id);
    return v ? v : find_vlr(evlrs, "LASF_Projection", id);
}

std::string describe(const Vlr& v) {
    return std::string("LASF_Projection ") + std::to_string(v.record_id) + (v.extended ? " EVLR" : " VLR") +
           " at offset " + std::to_string(v.header_offset);
}

std::vector<std::uint8_t> load_record(const io::File& file, const Vlr* v, Diagnostics& warnings) {
    if (!v) return {};
    if (v->data_size > kMaxCrsRecordBytes) {
        warnings.warn(describe(*v) + " is " + std::to_string(v->data_size) + " bytes; ignored", v->header_offset);
        return {};
    }
    return vlr_payload(file, *v);
}

// Runs a parser and prefixes its warnings with the record they are about.
template <typename Parse>
Crs parse_record(const Vlr& record, Diagnostics& warnings, Parse parse) {
    Crs c = parse();
    for (const auto& w : c.warnings) {
        warnings.add({w.level, w.file, record.header_offset, describe(record) + ": " + w.message});
    }
    c.warnings.clear();
    return c;
}

std::optional<Crs> wkt_of_file(const std::vector<Vlr>& vlrs, const std::vector<Vlr>& evlrs, const io::File& file,
                               Diagnostics& warnings, std::string& text) {
    const Vlr* record = find_projection_record(vlrs, evlrs, 2112);
    if (!record) return std::nullopt;
    auto bytes = load_record(file, record, warnings);
    text.assign(bytes.begin(), std::find(bytes.begin(), bytes.end(), std::uint8_t{0}));
    Crs c = parse_record(*record, warnings, [&] { return parse_wkt_crs(text); });
    if (c.source == "none") return std::nullopt;
    return c;
}

std::optional<Crs> geotiff_of_file(const std::vector<Vlr>& vlrs, const std::vector<Vlr>& evlrs, const io::File& file,
                                   Diagnostics& warnings) {
    const Vlr* dir = find_projection_record(vlrs, evlrs, kTagKeyDirectory);
    if (!dir) return std::nullopt;
    const auto keys = load_record(file, dir, warnings);
    const auto doubles = load_record(file, find_projection_record(vlrs, evlrs, kTagDoubleParams), warnings);
    const auto ascii = load_record(file, find_projection_record(vlrs, evlrs, kTagAsciiParams), warnings);
    Crs c = parse_record(*dir, warnings, [&] { return parse_geotiff_crs(keys, doubles, ascii); });
    if (c.source == "none") return std::nullopt;
    return c;
}

std::string epsg_text(const std::optional<int>& code) {
    return code ? "EPSG:" + std::to_string(*code) : "no EPSG code";
}

std::string record_kind(const Crs& c) { return c.source == "wkt" ? "WKT record" : "GeoTIFF keys"; }

void compare(const Crs& used, const Crs& other, Diagnostics& warnings) {
    const std::string a = "the " + record_kind(used), b = " but the " + record_kind(other);
    const std::string tail = "; using the " + record_kind(used);
    if (other.epsg && used.epsg != other.epsg) {
        warnings.warn(a + " give " + epsg_text(used.epsg) + b + " give " + epsg_text(other.epsg) + tail);
    }
    const LinearUnit ua = used.horizontal_unit, ub = other.horizontal_unit;
    if (ua != LinearUnit::Unknown && ub != LinearUnit::Unknown && ua != ub) {
        warnings.warn(a + " give horizontal unit " + unit_name(ua) + b + " give " + unit_name(ub) + tail);
    }
}

}  // namespace

const char* unit_name(LinearUnit unit) {
    switch (unit) {
        case LinearUnit::Metre: return "metre";
        case LinearUnit::InternationalFoot: return "foot";
        case LinearUnit::UsSurveyFoot: return "us_survey_foot";
        case LinearUnit::Other: return "other";
        case LinearUnit::Unknown: break;
    }
    return "unknown";
}

double unit_to_metres(LinearUnit unit) {
    switch (unit) {
        case LinearUnit::Metre: return 1.0;
        case LinearUnit::InternationalFoot: return kFootMetres;
        case LinearUnit::UsSurveyFoot: return kUsSurveyFootMetres;
        default: return kNaN;
    }
}

double Crs::z_to_metres() const {
    if (std::isfinite(vertical_to_metres)) return vertical_to_metres;
    return geographic ? kNaN : horizontal_to_metres;
}

LinearUnit projected_unit_of_epsg(int code) {
    if (listed(kUsFootProjected, code)) return LinearUnit::UsSurveyFoot;
    if (listed(kFootProjected, code)) return LinearUnit::InternationalFoot;
    for (const auto& r : kMetreProjected) {
        if (code >= r.first && code <= r.last) return LinearUnit::Metre;
    }
    return LinearUnit::Unknown;
}

LinearUnit vertical_unit_of_epsg(int code) {
    if (listed(kUsFootVertical, code)) return LinearUnit::UsSurveyFoot;
    if (listed(kFootVertical, code)) return LinearUnit::InternationalFoot;
    if (listed(kMetreVertical, code)) return LinearUnit::Metre;
    return LinearUnit::Unknown;
}

Crs parse_geotiff_crs(std::span<const std::uint8_t> key_directory, std::span<const std::uint8_t> double_params,
                      std::span<const std::uint8_t> ascii_params) {
    Diagnostics warnings;
    const GeoKeys keys = decode_geokeys(key_directory, double_params, ascii_params, warnings);
    Crs c;
    if (!keys.shorts.empty() || !keys.doubles.empty() || !keys.strings.empty()) c = crs_from_geokeys(keys, warnings);
    else warnings.warn("the GeoKeyDirectory holds no usable key");
    c.warnings = std::move(warnings);
    return c;
}

Crs parse_wkt_crs(std::string_view wkt) {
    Diagnostics warnings;
    Crs c;
    while (!wkt.empty() && std::isspace(static_cast<unsigned char>(wkt.back()))) wkt.remove_suffix(1);
    if (wkt.find_first_not_of(" \t\r\n") == std::string_view::npos) {
        warnings.warn("the WKT record is empty");
    } else {
        try {
            bool trailing = false;
            const WktNode root = WktReader(wkt).read(trailing);
            if (trailing) warnings.warn("text after the end of the WKT root element (unbalanced brackets?) ignored");
            c = crs_from_wkt(root, warnings);
        } catch (const WktSyntaxError& e) {
            warnings.warn("WKT syntax error at character " + std::to_string(e.position) + ": " + e.what);
        }
    }
    if (c.source == "wkt") c.wkt = std::string(wkt);
    c.warnings = std::move(warnings);
    return c;
}

Crs read_crs(const std::vector<Vlr>& vlrs, const std::vector<Vlr>& evlrs, const io::File& file, bool wkt_flag) {
    Diagnostics warnings;
    std::string wkt_text;
    std::optional<Crs> wkt = wkt_of_file(vlrs, evlrs, file, warnings, wkt_text);
    std::optional<Crs> geotiff = geotiff_of_file(vlrs, evlrs, file, warnings);

    std::optional<Crs>& preferred = wkt_flag ? wkt : geotiff;
    std::optional<Crs>& fallback = wkt_flag ? geotiff : wkt;
    Crs out;
    if (preferred) {
        out = std::move(*preferred);
        if (fallback) compare(out, *fallback, warnings);
    } else if (fallback) {
        out = std::move(*fallback);
        warnings.warn(wkt_flag ? "the header's WKT bit is set but there is no usable WKT record; using the GeoTIFF keys"
                               : "the header's WKT bit is not set but the only usable CRS record is WKT; using it");
    }
    if (out.wkt.empty()) out.wkt = std::move(wkt_text);  // the text even when it was unusable
    out.warnings = std::move(warnings);
    return out;
}

}  // namespace lidarscout::las
