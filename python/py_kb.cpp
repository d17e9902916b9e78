// stepstone.KnowledgeBase: kb::KnowledgeBase with numpy arrays in and out,
// saved to and opened from the KB files of `stepstone kb`.

#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>

#include "bindings.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "db/kb_store.hpp"
#include "kb/knowledge_base.hpp"
#include "runs/kb_files.hpp"

namespace stepstone::python {

namespace {

// A KB as Python holds it. `views` counts the live arrays that look into the
// KB's segments without a copy (KnowledgeBase.segments); a change that could
// move the segments is refused while one lives, as numpy refuses to resize an
// array that others reference.
//
// Python threads may share one KB: the calls that release the GIL run C++ at
// once, so `lock` orders them. A change (observe, merge) takes it alone, every
// read shares it, so lookups stay concurrent. The lock is always taken after
// the GIL is released (or while holding it, by calls that never release it and
// wait only for C++ work that does not need the GIL), so the two cannot deadlock.
struct PyKb {
    kb::KnowledgeBase kb;
    std::string name;  // as stored in a file ("" for a KB built in Python)
    std::optional<std::uint64_t> randomized_seed;
    std::shared_ptr<std::atomic<int>> views = std::make_shared<std::atomic<int>>(0);
    std::shared_ptr<std::shared_mutex> lock = std::make_shared<std::shared_mutex>();

    std::shared_lock<std::shared_mutex> reading() const { return std::shared_lock(*lock); }
    std::unique_lock<std::shared_mutex> writing() const { return std::unique_lock(*lock); }

    explicit PyKb(kb::KnowledgeBase k, std::string n = {}, std::optional<std::uint64_t> seed = std::nullopt)
        : kb(std::move(k)), name(std::move(n)), randomized_seed(seed) {}

    void check_unviewed(const char* what) const {
        if (*views > 0) {
            throw py::buffer_error(concat("KnowledgeBase.", what, ": ", views->load(),
                                          " array(s) from .segments still view this KB; delete them or "
                                          "take a copy (np.array(kb.segments)) first"));
        }
    }
};

// What a lookup found, one entry per policy segment.
struct PyLookup {
    py::array_t<std::int64_t> ids;  // KB segment id, -1 for none
    py::array_t<double> distances;
    py::array_t<double> averages;
    double r_max = 0.0;
};

// The records of a KB flattened into one numpy structured row each.
struct RecordRow {
    double cum_reward;
    std::uint64_t count;
    double average;
    std::uint32_t first_source;
    std::int64_t first_generation;
    std::uint32_t last_source;
    std::int64_t last_generation;
};

struct SourceRow {
    std::int64_t first_generation;
    std::int64_t last_generation;
    std::uint64_t policies;
};

kb::Match match_of(const std::string& text) { return db::parse_match(text, "match"); }

kb::Segments segments_of(const PyKb& self, const FloatArray& behaviour) {
    const kb::KbParams& params = self.kb.params();
    const auto values = behaviour_values(behaviour, params.channels, "behaviour");
    return kb::segment_behaviour(values, params.channels, params.segment_width);
}

PyLookup lookup(const PyKb& self, const FloatArray& behaviour) {
    const kb::Segments segments = segments_of(self, behaviour);
    kb::Lookup found;
    {
        py::gil_scoped_release release;
        const auto shared = self.reading();
        found = self.kb.lookup(segments);
    }
    const auto n = static_cast<py::ssize_t>(found.segments.size());
    PyLookup out{py::array_t<std::int64_t>(n), py::array_t<double>(n), py::array_t<double>(n), found.r_max};
    auto ids = out.ids.mutable_unchecked<1>();
    auto distances = out.distances.mutable_unchecked<1>();
    auto averages = out.averages.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) {
        const kb::SegmentMatch& match = found.segments[static_cast<std::size_t>(i)];
        ids(i) = match.id ? static_cast<std::int64_t>(*match.id) : -1;
        distances(i) = match.distance;
        averages(i) = match.average_reward;
    }
    return out;
}

double r_max(const PyKb& self, const FloatArray& behaviour) {
    const kb::Segments segments = segments_of(self, behaviour);
    py::gil_scoped_release release;
    const auto shared = self.reading();
    return self.kb.r_max(segments);
}

py::dict observe(PyKb& self, const FloatArray& behaviour, double reward, const std::string& run,
                 std::int64_t generation) {
    const kb::Segments segments = segments_of(self, behaviour);
    kb::ObserveResult result;
    {
        py::gil_scoped_release release;
        const auto alone = self.writing();
        self.check_unviewed("observe");  // under the lock: no view can appear before the change
        kb::check_run_name(run, "run");
        const std::uint32_t source = self.kb.add_source(run);
        result = self.kb.observe(segments, reward, kb::Origin{source, generation});
    }
    py::dict out;
    out["matched"] = result.matched;
    out["inserted"] = result.inserted;
    return out;
}

// a read-only (segments x width x channels) view of the KB's values; the array
// keeps the KB alive and counts itself in `views` while it lives
py::array segments_view(py::object owner) {
    PyKb& self = owner.cast<PyKb&>();
    const auto shared = self.reading();  // no change is under way while the view is made
    const kb::KbParams& params = self.kb.params();
    struct Token {
        std::shared_ptr<std::atomic<int>> views;
        py::object owner;
    };
    ++*self.views;
    py::capsule base(new Token{self.views, owner}, [](void* pointer) {
        auto* token = static_cast<Token*>(pointer);
        --*token->views;
        delete token;
    });
    const auto width = static_cast<py::ssize_t>(params.segment_width);
    const auto channels = static_cast<py::ssize_t>(params.channels);
    const auto f = static_cast<py::ssize_t>(sizeof(float));
    py::array view(py::dtype::of<float>(), {static_cast<py::ssize_t>(self.kb.size()), width, channels},
                   {width * channels * f, channels * f, f}, self.kb.values().data(), base);
    py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return view;
}

py::array_t<RecordRow> records(const PyKb& self) {
    const auto shared = self.reading();
    py::array_t<RecordRow> out(static_cast<py::ssize_t>(self.kb.size()));
    auto rows = out.mutable_unchecked<1>();
    for (std::size_t i = 0; i < self.kb.size(); ++i) {
        const kb::SegmentRecord& r = self.kb.record(i);
        rows(static_cast<py::ssize_t>(i)) =
            RecordRow{r.cum_reward,       r.count,       r.average(),      r.first.source,
                      r.first.generation, r.last.source, r.last.generation};
    }
    return out;
}

py::list sources(const PyKb& self) {
    const auto shared = self.reading();
    py::list out;
    for (const kb::Source& source : self.kb.sources()) {
        py::dict row;
        row["run"] = source.run;
        row["first_generation"] = source.first_generation;
        row["last_generation"] = source.last_generation;
        row["policies"] = source.policies;
        out.append(row);
    }
    return out;
}

void save(const PyKb& self, const std::filesystem::path& path, const std::optional<std::string>& name,
          bool force) {
    const std::string stored = name ? *name : (self.name.empty() ? std::string("kb") : self.name);
    kb::check_run_name(stored, "name");
    py::gil_scoped_release release;
    const auto shared = self.reading();
    runs::save_kb_file(path, force, stored, self.kb, self.randomized_seed);
}

PyKb open(const std::filesystem::path& path, const std::optional<std::string>& name) {
    db::StoredKb stored;
    {
        py::gil_scoped_release release;
        stored = runs::load_kb_file(path, name.value_or(""));
    }
    return PyKb(std::move(stored.kb), stored.name, stored.randomized_seed);
}

std::string repr(const PyKb& self) {
    const auto shared = self.reading();
    const kb::KbParams& p = self.kb.params();
    return concat("<stepstone.KnowledgeBase", self.name.empty() ? "" : concat(" '", self.name, "'"), ": ",
                  self.kb.size(), " segments of ", p.segment_width, " x ", p.channels, ", delta ",
                  shortest(p.delta), ", ", db::to_string(p.match),
                  p.counting == kb::Counting::occurrence ? "" : ", counting by policy", ">");
}

// seconds the C++ side takes for lookup() (or r_max()) of every policy of a
// (policies x steps x channels) array, timed in this process: the baseline of
// the Python calls' rate (examples/python/lookup_speed.py)
double time_lookups(const PyKb& self, const FloatArray& behaviours, bool r_max_only) {
    if (behaviours.ndim() != 3 ||
        static_cast<std::size_t>(behaviours.shape(2)) != self.kb.params().channels) {
        throw py::value_error("behaviours must be a (policies x steps x channels) array");
    }
    const auto per_policy = static_cast<std::size_t>(behaviours.shape(1) * behaviours.shape(2));
    const auto policies = static_cast<std::size_t>(behaviours.shape(0));
    const kb::KbParams& params = self.kb.params();
    py::gil_scoped_release release;
    const auto shared = self.reading();
    double sink = 0.0;
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < policies; ++i) {
        const std::span<const float> values(behaviours.data() + i * per_policy, per_policy);
        const kb::Segments segments = kb::segment_behaviour(values, params.channels, params.segment_width);
        sink += r_max_only ? self.kb.r_max(segments) : self.kb.lookup(segments).r_max;
    }
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    return sink >= 0.0 ? elapsed.count() : -elapsed.count();  // (keeps the loop from being dropped)
}

}  // namespace

void bind_kb(py::module_& m) {
    PYBIND11_NUMPY_DTYPE(RecordRow, cum_reward, count, average, first_source, first_generation, last_source,
                         last_generation);

    py::class_<PyLookup>(m, "Lookup", "What KnowledgeBase.lookup found for a policy's segments.")
        .def_readonly("ids", &PyLookup::ids,
                      "int64 array: the KB segment credited to each policy segment, -1 for none")
        .def_readonly("distances", &PyLookup::distances,
                      "float64 array: Euclidean distance to it (0 for none)")
        .def_readonly("averages", &PyLookup::averages, "float64 array: its average reward (0 for none)")
        .def_readonly("r_max", &PyLookup::r_max,
                      "the largest average among the segments, a segment without a match counting 0")
        .def(
            "__len__", [](const PyLookup& l) { return l.ids.size(); }, "the number of policy segments")
        .def("__repr__", [](const PyLookup& l) {
            return concat("<stepstone.Lookup: ", l.ids.size(), " segments, r_max ", shortest(l.r_max), ">");
        });

    py::class_<PyKb>(m, "KnowledgeBase", R"(The paper's knowledge base: behaviour segments with the cumulated
reward and the number of the policies that exhibited them.

A behaviour is a (steps x channels) matrix, one row per time step; it is cut
into non-overlapping segments of `width` rows (a trailing partial one is
dropped). observe() credits each segment to the nearest KB segment closer than
`delta` (Euclidean, ties to the lowest id) or inserts it; lookup() finds each
segment's match under `match` and the policy's r_max, the largest average
reward among them. Segments are stored as float32; ids are insertion order.
Every answer is exact and independent of threads.

>>> kb = stepstone.KnowledgeBase(width=20, channels=15, delta=1.83)
>>> kb.observe(behaviour, reward=0.25, run="my-run", generation=0)
>>> kb.lookup(other_behaviour).r_max
>>> kb.save("kb.db"); stepstone.KnowledgeBase.open("kb.db"))")
        .def(py::init([](std::size_t width, std::size_t channels, double delta, const std::string& match,
                         const std::string& counting) {
                 kb::KbParams params{width, channels, delta, match_of(match),
                                     kb::parse_counting(counting, "counting")};
                 return PyKb(kb::KnowledgeBase(params));
             }),
             py::arg("width") = kb::kDefaultSegmentWidth, py::arg("channels") = 15, py::arg("delta") = 1.83,
             py::arg("match") = "within_delta", py::arg("counting") = "occurrence",
             "An empty KB: segments of `width` time steps of `channels` values, threshold `delta`, lookup "
             "rule `match` ('within_delta' or 'nearest'), credit rule `counting` ('occurrence': every "
             "matching segment of a policy; 'policy': each KB segment once per policy). Raises ConfigError "
             "for a bad value.")
        .def_static(
            "open", &open, py::arg("path"), py::arg("name") = py::none(),
            "The KB called `name` of a KB or run file (default: the file's only KB), opened read-only. "
            "Raises DatabaseError or DataError naming the file.")
        .def("save", &save, py::arg("path"), py::arg("name") = py::none(), py::arg("force") = false,
             "Writes this KB as the only content of a new KB file (the format of `stepstone kb export`), "
             "atomically. `name` defaults to the KB's own name, or 'kb'. An existing file is refused unless "
             "`force`.")
        .def(
            "observe", &observe, py::arg("behaviour"), py::arg("reward"), py::arg("run") = "python",
            py::arg("generation") = 0,
            "Observes one policy that obtained `reward` and showed `behaviour` (steps x channels), as the "
            "paper's rule: each segment in order credits its nearest KB segment closer than delta "
            "(cum_reward += reward, count += 1) or is inserted. `run` names the source (registered on first "
            "use). Returns {'matched': n, 'inserted': n}. Raises DataError for a non-finite value; the KB is "
            "then unchanged.")
        .def("lookup", &lookup, py::arg("behaviour"),
             "Each segment's match under the KB's rule and the policy's r_max, as a Lookup.")
        .def("r_max", &r_max, py::arg("behaviour"),
             "lookup(behaviour).r_max, bit for bit, without the per-segment lists.")
        .def(
            "merge",
            [](PyKb& self, const PyKb& other) {
                py::gil_scoped_release release;
                // the two locks in one order (by address), so that a.merge(b) and b.merge(a) cannot deadlock
                if (&self == &other) {
                    const auto alone = self.writing();
                    self.check_unviewed("merge");
                    self.kb.merge(other.kb);
                    return;
                }
                std::unique_lock<std::shared_mutex> mine(*self.lock, std::defer_lock);
                std::shared_lock<std::shared_mutex> theirs(*other.lock, std::defer_lock);
                if (self.lock.get() < other.lock.get()) {
                    mine.lock();
                    theirs.lock();
                } else {
                    theirs.lock();
                    mine.lock();
                }
                self.check_unviewed("merge");
                self.kb.merge(other.kb);
            },
            py::arg("other"),
            "Observes every segment of `other` into this KB under this KB's delta, adding cumulated rewards "
            "and counts; its sources are appended. Raises DataError if width, channels or delta differ.")
        .def(
            "randomized",
            [](const PyKb& self, std::uint64_t seed) {
                const auto shared = self.reading();
                return PyKb(self.kb.randomized(seed), self.name.empty() ? "" : self.name + "-rand", seed);
            },
            py::arg("seed"),
            "A copy whose averages are drawn from U[0, 1) (the `-rand` controls), as `stepstone kb randomize "
            "--seed`.")
        .def(
            "coarsened",
            [](const PyKb& self, double delta) {
                const auto shared = self.reading();
                return PyKb(self.kb.coarsened(delta), self.name);
            },
            py::arg("delta"),
            "This KB's segments re-observed under a larger threshold, as `kb export --delta`.")
        .def(
            "nearest",
            [](const PyKb& self, const FloatArray& segment) -> py::object {
                if (static_cast<std::size_t>(segment.size()) != self.kb.params().dim()) {
                    throw py::value_error(concat("segment has ", segment.size(),
                                                 " values, the KB's segments have ", self.kb.params().dim()));
                }
                const auto shared = self.reading();
                const auto found =
                    self.kb.nearest({segment.data(), static_cast<std::size_t>(segment.size())});
                if (!found) return py::none();
                return py::make_tuple(found->id, std::sqrt(found->squared_distance));
            },
            py::arg("segment"),
            "(id, distance) of the KB segment nearest to one segment (width x channels values), None if "
            "empty.")
        .def_property_readonly(
            "segments", &segments_view,
            "float32 array (segments x width x channels), read-only, viewing the KB's memory "
            "(no copy); observe() and merge() refuse while such a view lives.")
        .def_property_readonly(
            "records", &records,
            "structured array, one row per segment: cum_reward, count, average, first_source, "
            "first_generation, last_source, last_generation (a copy).")
        .def_property_readonly("sources", &sources,
                               "the runs that fed the KB: dicts of run, first_generation, last_generation, "
                               "policies.")
        .def_property_readonly(
            "width", [](const PyKb& s) { return s.kb.params().segment_width; }, "time steps per segment")
        .def_property_readonly(
            "channels", [](const PyKb& s) { return s.kb.params().channels; }, "values per time step")
        .def_property_readonly(
            "delta", [](const PyKb& s) { return s.kb.params().delta; },
            "Euclidean threshold: a segment closer than delta is credited")
        .def_property_readonly(
            "match", [](const PyKb& s) { return std::string(db::to_string(s.kb.params().match)); },
            "lookup rule: 'within_delta' or 'nearest'")
        .def_property_readonly(
            "counting", [](const PyKb& s) { return std::string(kb::to_string(s.kb.params().counting)); },
            "observe's credit rule: 'occurrence' or 'policy'")
        .def_property_readonly(
            "name", [](const PyKb& s) { return s.name; }, "the KB's name in its file ('' if none)")
        .def_property_readonly(
            "randomized_seed", [](const PyKb& s) { return s.randomized_seed; },
            "the seed of a randomized KB, else None")
        .def_property_readonly(
            "max_average",
            [](const PyKb& s) {
                const auto shared = s.reading();
                return s.kb.max_average();
            },
            "the largest average reward (0 if empty): the `sum` treatment's normaliser")
        .def(
            "__len__",
            [](const PyKb& s) {
                const auto shared = s.reading();
                return s.kb.size();
            },
            "the number of segments")
        .def("__repr__", &repr);

    m.def(
        "_time_lookups", &time_lookups, py::arg("kb"), py::arg("behaviours"), py::arg("r_max_only") = false,
        "Seconds the library takes to look every policy of a (policies x steps x channels) array up in `kb`, "
        "in a C++ loop (the baseline of examples/python/lookup_speed.py).");
}

}  // namespace stepstone::python
