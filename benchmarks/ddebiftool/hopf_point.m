function [hopf,stbr,funcs,ip,hbr]=hopf_point(tau,kstart,verbose,which,krange)
%% steady (drifting) state at defaults, continued in k from kstart over krange
% (default 3), Hopf located: the which-th change of the number of unstable
% complex pairs (default the first)
if nargin<3, verbose=true; end
if nargin<4, which=1; end
if nargin<5, krange=3; end
[funcs,ip]=slope_funcs();
par=zeros(1,8);
par([ip.k,ip.tau,ip.c,ip.a,ip.b,ip.cc,ip.d,ip.v])=[kstart,tau,0,3.2,7.2,4.8,1e-4,0.1];
F1=3*3.2*0.1^2-2*7.2*0.1+4.8; sy0=1e-4/F1;
x0=[0;0;sy0/kstart;sy0;0];
dk=0.05*krange/3;     % 0.05 over the default range of 3
[stbr,suc]=SetupStst(funcs,'x',x0,'parameter',par,'contpar',[ip.k,ip.c],...
    'dir',ip.k,'step',dk,'max_step',[ip.k,dk],'max_bound',[ip.k,kstart+krange]);
if ~suc, error('stst init failed'); end
stbr.method.continuation.plot=0;
stbr.method.point.extra_condition=1;   % activate the pinning z=0 (sys_cond)
stbr=br_contn(funcs,stbr,200);
stbr.method.stability.minimal_real_part=-0.5;
stbr=br_stabl(funcs,stbr,0,1);
% eigenvalue 0 from the z-translation is present in the linearisation
% (it is removed only by the extra condition), so count complex pairs only
nun=arrayfun(@(p)sum(real(p.stability.l0)>0 & abs(imag(p.stability.l0))>1e-6),stbr.point);
ih=find(diff(nun)~=0,which,'first');
if numel(ih)<which, error('no Hopf number %d found',which); end
ih=ih(which);
[hbr,suc]=SetupHopf(funcs,stbr,ih,'contpar',[ip.k,ip.c],'dir',[]);
if ~suc, error('Hopf correction failed'); end
hbr.method.point.extra_condition=1;
[hopf,suc]=p_correc(funcs,hbr.point(1),[ip.k,ip.c],[],hbr.method.point);
if ~suc, error('pinned Hopf correction failed'); end
hbr.point(1)=hopf;
if verbose
    fprintf('HOPF tau=%g k_H=%.8f omega=%.8f period=%.8f drift_c=%.3e s_y=%.6e\n',...
        tau,hopf.parameter(ip.k),hopf.omega,2*pi/hopf.omega,hopf.parameter(ip.c),hopf.x(4));
end
end
