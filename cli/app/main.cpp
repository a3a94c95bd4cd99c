#include "cli/commands.h"

int main(int argc, char** argv) {
    return stsv::runCli(argc, argv);
}
