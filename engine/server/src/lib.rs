//! Provisioning and control of a local rcssservermj: virtualenv, process, monitor port.
