from vslsp.cli import main

if __name__ == "__main__":  # not when a spawned child process imports it as its __mp_main__
    main()
