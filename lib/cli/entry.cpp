#include "cli/entry.hpp"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <new>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "core/error.hpp"
#include "core/text.hpp"
#include "core/files.hpp"
#include "core/number.hpp"
#include "version.hpp"

namespace tp::cli {
namespace {

// One line, printable: a trailing newline goes; any other control character or byte that
// is not UTF-8 (a newline, a NUL, a terminal's escape, from argv or a file) is escaped
// (core/text.hpp), whoever made the message (tp::Error's are already, CLI11's are not).
std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return printable(s);
}

// --output: its path, and the file once the options are parsed.
std::string g_output_path;
std::unique_ptr<AtomicFile> g_output;

int report(const std::string& program, const std::string& message, ExitCode code) {
  g_output.reset();  // a document not complete is not written (its temporary removed)
  std::fflush(stdout);
  std::fprintf(stderr, "%s: %s\n", program.c_str(), one_line(message).c_str());
  return static_cast<int>(code);
}

std::string option_name(const CLI::Option& opt) {
  return !opt.get_lnames().empty()   ? "--" + opt.get_lnames().front()
         : !opt.get_snames().empty() ? "-" + opt.get_snames().front()
                                     : opt.get_name(true);
}

// Every option and positional of `app` and its option groups.
void each_option(CLI::App& app, const std::function<void(CLI::Option&)>& f) {
  for (CLI::Option* opt : app.get_options()) f(*opt);
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) each_option(*sub, f);
}

// An option that takes one value takes it once: given twice, it is refused (CLI11's Throw
// policy, made explicit here so that no program can take the last silently), and the
// message says so: "--at: given 2 times ('1,2', '3,4'); give it once".
void refuse_repeats(CLI::App& app) {
  each_option(app, [](CLI::Option& opt) {
    if (opt.get_type_size_max() > 0 && opt.get_items_expected_max() == 1)
      opt.multi_option_policy(CLI::MultiOptionPolicy::Throw);
  });
}

std::string repeated_option_text(CLI::App& app) {
  std::string text;
  each_option(app, [&](CLI::Option& opt) {
    if (!text.empty() || opt.get_type_size_max() == 0 || opt.get_items_expected_max() != 1 ||
        opt.results().size() < 2)
      return;
    std::string values;
    for (const std::string& v : opt.results())
      values += (values.empty() ? "" : ", ") + quoted_text(v);
    text = option_name(opt) + ": given " + std::to_string(opt.results().size()) + " times (" +
           values + "); give it once";
  });
  return text;
}

// An option given with an empty value (--width '', --width=) is refused, naming it: an empty
// string never means "not given".  Flags take no value and are skipped.
void refuse_empty_values(const CLI::App& app) {
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_type_size_max() == 0) continue;
    for (const std::string& value : opt->results())
      if (value.empty()) bad_input(option_name(*opt) + ": empty value");
  }
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    refuse_empty_values(*sub);
}

// A signal that ends the program removes the temporaries of files not yet complete
// (core/files.hpp), then ends it as the signal would have.
void end_by_signal(int sig) {
  remove_temporaries();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void install_cleanup_handlers() {
  for (int sig : {SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGPIPE}) {
    struct sigaction old {};
    if (sigaction(sig, nullptr, &old) != 0 || old.sa_handler == SIG_IGN) continue;
    struct sigaction sa {};
    sa.sa_handler = end_by_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, nullptr);
  }
}

}  // namespace

void add_output_option(CLI::App& app) {
  app.add_option("--output", g_output_path,
                 "Write the document to FILE instead of stdout: whole when the program "
                 "succeeds, and FILE left as it was when it fails or is interrupted")
      ->type_name("FILE");
}

int run(CLI::App& app, int argc, char** argv, const std::function<void()>& body) {
#if defined(__GLIBC__)
  // The programs allocate and free matrices of tens of MB over and over (a focus's sample
  // rows, a plane's grid, each round): glibc would hand each back to the system (mmap and
  // trim) and fault its pages in again on the next, which in a virtual machine cost about
  // a fifth of an 8 x 8 pixel's time (rect3d RA: 1.07 s against 0.88 s).  Freed memory is
  // kept for reuse instead, until the program ends.
  // (32 MiB: mmap's largest threshold on 64-bit systems, mallopt(3).)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  const std::string program = app.get_name();
  app.set_version_flag("--version", program + " " + TP_VERSION);
  // --name= gives the option an empty value: refused as refuse_empty_values refuses --name ''.
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") break;
    if (arg.size() > 3 && arg.compare(0, 2, "--") == 0 && arg.back() == '=' &&
        arg.find('=') == arg.size() - 1)
      return report(program, arg.substr(0, arg.size() - 1) + ": empty value", ExitCode::bad_input);
  }
  refuse_repeats(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::CallForVersion& e) {
    std::cout << e.what() << "\n";
    return 0;
  } catch (const CLI::ArgumentMismatch& e) {
    const std::string repeated = repeated_option_text(app);
    return report(program, repeated.empty() ? std::string(e.what()) + " (see --help)" : repeated,
                  ExitCode::bad_input);
  } catch (const CLI::ParseError& e) {
    return report(program, std::string(e.what()) + " (see --help)", ExitCode::bad_input);
  } catch (const Error& e) {  // an option's own parser (add_integer, add_seed)
    return report(program, e.what(), e.code());
  }
  try {
    refuse_empty_values(app);
    install_cleanup_handlers();
    if (!g_output_path.empty() && g_output_path != "-")
      g_output = std::make_unique<AtomicFile>(g_output_path, "--output");
    body();
    if (std::fflush(stdout) != 0 || std::ferror(stdout))
      failure(std::string("write error on stdout: ") + std::strerror(errno));
    if (g_output) g_output->commit();
    g_output.reset();
    return 0;
  } catch (const Told& e) {
    g_output.reset();
    std::fflush(stdout);
    return static_cast<int>(e.code());
  } catch (const Error& e) {
    return report(program, e.what(), e.code());
  } catch (const CLI::Error& e) {
    return report(program, e.what(), ExitCode::bad_input);
  } catch (const std::bad_alloc&) {
    return report(program, "out of memory", ExitCode::failure);
  } catch (const std::exception& e) {
    return report(program, std::string("internal error: ") + e.what(), ExitCode::failure);
  }
}

namespace {

template <class T>
CLI::Option* add_integer_option(CLI::App& app, const std::string& name, T& target,
                                const std::string& help, T lo, T hi) {
  return app
      .add_option_function<std::string>(
          name,
          [&target, name, lo, hi](const std::string& text) {
            if (text.empty()) return;  // refused as an empty value after parsing
            target = static_cast<T>(parse_integer(text, name, lo, hi));
          },
          help)
      ->type_name("N");
}

}  // namespace

CLI::Option* add_integer(CLI::App& app, const std::string& name, int& target,
                         const std::string& help, int lo, int hi) {
  return add_integer_option(app, name, target, help, lo, hi);
}

CLI::Option* add_integer(CLI::App& app, const std::string& name, long& target,
                         const std::string& help, long lo, long hi) {
  return add_integer_option(app, name, target, help, lo, hi);
}

CLI::Option* add_seed(CLI::App& app, const std::string& name, std::uint64_t& target,
                      const std::string& help) {
  return app
      .add_option_function<std::string>(
          name,
          [&target, name](const std::string& text) {
            if (!text.empty()) target = parse_unsigned(text, name);
          },
          help)
      ->type_name("S");
}

void add_skin_flags(CLI::App& app, const std::string& skin_flag,
                    const std::string& compliance_flag, std::string& path,
                    std::string& compliance, const std::string& record,
                    const std::string& only) {
  app.add_option(skin_flag, path,
                 (only.empty() ? "The" : only + "the") +
                     " skin the electrodes touch (docs/skin.md): each pulse's voltage and "
                     "impedance per channel in " + record +
                     "; events script contact and sweat [none: an ideal load]")
      ->type_name("FILE");
  app.add_option(compliance_flag, compliance,
                 "With " + skin_flag +
                     ": the output stage's compliance voltage, 1 to 1000 V [100]")
      ->type_name("V");
}

void write_stdout(std::string_view text) {
  if (g_output) {
    g_output->write(text);
    return;
  }
  if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0)
    failure(std::string("write error on stdout: ") + std::strerror(errno));
}

}  // namespace tp::cli
