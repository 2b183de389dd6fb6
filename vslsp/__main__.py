from vslsp.cli import main

main()
