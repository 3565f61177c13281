// Placeholder front end; replaced by the component's real command.
int main() { return 2; }
